"""The catalogue's models, prebuilt: ``hamel.models.MobileRobot``, ``WhippleBicycle``,
``ChaplyginSleigh``, ``RollingDisk``, ``ChaplyginBall``, ``Rattleback``, ``KnifeEdge``,
``VerticalDisk``, ``BallOnTurntable``, ``ContactOscillator``, ``MobileRobotPaper`` and the
N-trailers ``NTrailer1``, ``NTrailer2``, ``NTrailer8``. Each is the Rust catalogue's model
(``hamel::models``), with its parameters' defaults."""

from ._model import model_class
from ._native import models as _types

__all__ = sorted(_types)

for _name, _type in _types.items():
    globals()[_name] = model_class(_type, __name__)
del _name, _type
