"""hamel from Python: nonholonomic mechanical systems — wheels that roll without slipping,
skates, sleighs, balls, bicycles — compiled into fast simulators, driven from NumPy, pandas
and Jupyter with the whole solve in Rust.

>>> import hamel
>>> robot = hamel.models.MobileRobot(m0=10.0)
>>> run = robot.simulate(robot.state(alpha=0.3, w4=0.5, w5=0.4), t_end=10.0)
>>> run["x"][-1]  # doctest: +SKIP

:func:`compile` builds a model of your own from its Rust source (``#[hamel_system]``).
"""

from . import errors, models
from ._compile import compile, load
from ._linear import Linearization, Lqr, Mode
from ._model import Event, Model, Names, Parameters
from ._run import EventRecord, Run, Summary
from ._scene import Scene
from ._study import study
from ._table import Table
from .errors import CompileError, Error

__version__ = "0.1.0"

__all__ = [
    "CompileError", "Error", "Event", "EventRecord", "Linearization", "Lqr", "Mode", "Model",
    "Names", "Parameters", "Run", "Scene", "Summary", "Table", "compile", "errors", "load",
    "models", "study",
]

