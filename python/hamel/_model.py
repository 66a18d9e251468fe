"""The class of a model, the same for the catalogue's, a compiled model's and a crate's own:
parameters as keywords, names and units, states by name, runs, ensembles, linearizations,
scenes. The work is done by the Rust object behind it (``_native``)."""

from __future__ import annotations

import math
from typing import Callable, Dict, Iterable, Mapping, Optional, Sequence

import numpy as np

from ._linear import Linearization, Lqr
from ._run import Run
from ._scene import Scene
from ._table import Table


class Names(tuple):
    """Names of a model's quantities, in order, with their units (``.units``: a dict, ``None``
    where the model states none)."""

    units: Dict[str, Optional[str]]

    def __new__(cls, names: Iterable[str], units: Mapping[str, str]):
        self = super().__new__(cls, names)
        self.units = {n: units.get(n) for n in self}
        return self


class Parameters(dict):
    """A model's parameters by name, with ``.units`` and ``.docs`` (their doc comments)."""

    units: Dict[str, Optional[str]]
    docs: Dict[str, str]


class Event:
    """An event of a run: ``g(t, x)`` (a Python function, as scipy's ``solve_ivp`` takes) or a
    state component crossing a value (``Event("fallen", state="phi", value=1.0)``, evaluated
    in Rust). ``direction`` > 0 counts rising crossings only, < 0 falling ones, 0 both;
    ``terminal`` ends the run at the event's time."""

    def __init__(self, name: str, g: Optional[Callable] = None, *, state: Optional[str] = None,
                 value: float = 0.0, direction: float = 0.0, terminal: bool = False):
        if (g is None) == (state is None):
            raise TypeError("Event: give either a function g(t, x) or a state to watch (state=...)")
        if g is not None and not callable(g):
            raise TypeError(f"Event: g must be a function g(t, x), not {type(g).__name__}")
        self.name, self.g, self.state = name, g, state
        self.value, self.direction, self.terminal = float(value), float(direction), bool(terminal)

    def _spec(self):
        return (self.name, self.g, self.state, self.value, self.direction, self.terminal)


def _event_specs(events) -> list:
    specs = []
    for i, e in enumerate(events):
        if isinstance(e, Event):
            specs.append(e._spec())
        elif callable(e):
            # scipy's form: a function with optional attributes `terminal` and `direction`.
            name = getattr(e, "__name__", None) or f"event{i}"
            if name == "<lambda>":
                name = f"event{i}"
            specs.append((name, e, None, 0.0, float(getattr(e, "direction", 0.0)),
                          bool(getattr(e, "terminal", False))))
        else:
            raise TypeError(f"events[{i}]: expected a function g(t, x) or a hamel.Event, "
                            f"not {type(e).__name__}")
    return specs


def _columns(table) -> list:
    """(name, float array) pairs of a DataFrame or a dict of arrays."""
    if table is None:
        return []
    if hasattr(table, "columns") and hasattr(table, "__getitem__") and not isinstance(table, dict):
        names = list(table.columns)
        return [(str(n), np.ascontiguousarray(np.asarray(table[n], dtype=float))) for n in names]
    if isinstance(table, Mapping):
        return [(str(n), np.ascontiguousarray(np.atleast_1d(np.asarray(v, dtype=float))))
                for n, v in table.items()]
    raise TypeError(f"expected a DataFrame or a dict of arrays, not {type(table).__name__}")


class Model:
    """A model with its parameters. Subclasses (``hamel.models.MobileRobot``, a class from
    :func:`hamel.compile`) are made with their parameters as keywords, the others at the
    model's defaults: ``MobileRobot(m0=10.0)``."""

    _native_type = None
    _description: dict = {}

    def __init__(self, **parameters: float):
        native_type = type(self)._native_type
        if native_type is None:
            raise TypeError("hamel.Model is the base class of models; use one of hamel.models "
                            "or a class from hamel.compile")
        self._native = native_type.create(parameters)

    @classmethod
    def _from_native(cls, native):
        model = cls.__new__(cls)
        model._native = native
        return model

    # Names and units.

    @property
    def parameters(self) -> Parameters:
        d = self._description
        p = Parameters(zip(d["parameters"], self._native.parameter_values()))
        p.units = dict(zip(d["parameters"], d["parameter_units"]))
        p.docs = dict(zip(d["parameters"], d["parameter_docs"]))
        return p

    @classmethod
    def defaults(cls) -> Optional[Dict[str, float]]:
        """The parameters' defaults (the model's ``Default``), or ``None`` if it has none."""
        d = cls._description
        return None if d["defaults"] is None else dict(zip(d["parameters"], d["defaults"]))

    def _names(self, key: str) -> Names:
        return Names(self._description[key], self._description["units"])

    @property
    def coordinates(self) -> Names:
        return self._names("coordinates")

    @property
    def speeds(self) -> Names:
        """The free quasi-velocities."""
        return self._names("speeds")

    @property
    def state_names(self) -> Names:
        """The state's components: the coordinates, then the speeds."""
        return self._names("state")

    @property
    def inputs(self) -> Names:
        return self._names("inputs")

    @property
    def outputs(self) -> Names:
        return self._names("outputs")

    @property
    def constraints(self) -> tuple:
        return tuple(self._description["constraints"])

    @property
    def units(self) -> Dict[str, str]:
        """The units the model states (coordinates, speeds, inputs, ``t``, ``energy``)."""
        return dict(self._description["units"])

    # States.

    def state(self, t: float = 0.0, *, velocities: Optional[Mapping[str, float]] = None,
              **values: float) -> np.ndarray:
        """A state by the names of its coordinates and speeds, the rest zero, the dependent
        coordinates solved from the holonomic constraints (a value given for one is Newton's
        start). With ``velocities`` (by coordinate name) the speeds follow from them, after the
        constraints are checked."""
        return self._native.state(values, velocities, t)

    def with_parameters(self, **parameters: float) -> "Model":
        """The same model with some parameters changed."""
        return type(self)._from_native(self._native.with_parameters(parameters))

    # Runs.

    def simulate(self, x0, t_end: float = 10.0, dt: float = 0.01, method: str = "dopri5",
                 rtol: Optional[float] = None, atol: Optional[float] = None, *,
                 t0: float = 0.0, step: Optional[float] = None, inputs=None,
                 events: Sequence = (), lambdas: bool = False, project: bool = False,
                 max_steps: Optional[int] = None, max_step: Optional[float] = None,
                 initial_step: Optional[float] = None, min_step: Optional[float] = None,
                 max_samples: Optional[int] = None) -> Run:
        """Runs the model from ``x0`` (at ``t0``) to ``t_end``, sampled every ``dt``, the whole
        solve in Rust with the interpreter released (Ctrl-C stops it).

        ``method``: ``dopri5`` (``rtol``, ``atol``; defaults 1e-9, 1e-12), ``radau5``,
        ``rodas5p``, ``rodas4`` (stiff), ``rk4``, ``midpoint``, ``gauss2``, ``gauss3`` (fixed
        ``step``, default ``dt``).
        ``inputs``: constants (a number per input, or a dict by name), a function ``u(t, x)``,
        sampled arrays (a dict with the times under ``"t"``, linearly interpolated), or an
        :class:`~hamel.Lqr` design. ``events``: functions ``g(t, x)`` (scipy's form, with the
        attributes ``terminal`` and ``direction``) or :class:`~hamel.Event`\\ s. ``lambdas``:
        record the constraint forces. ``project``: keep holonomic constraints to rounding."""
        if isinstance(inputs, Lqr):
            inputs = inputs._native
        native = self._native.simulate(
            x0, t0=t0, t_end=t_end, dt=dt, method=method, rtol=rtol, atol=atol, step=step,
            max_steps=max_steps, max_step=max_step, initial_step=initial_step,
            min_step=min_step, inputs=inputs, events=_event_specs(events) if events else None,
            lambdas=lambdas, project=project, max_samples=max_samples)
        return Run(native, self)

    def ensemble(self, cases=None, *, parameters=None, states=None, t_end: float = 10.0,
                 dt: float = 0.01, method: str = "dopri5", rtol: Optional[float] = None,
                 atol: Optional[float] = None, t0: float = 0.0, step: Optional[float] = None,
                 inputs=None, events: Sequence = (), lambdas: bool = False,
                 project: bool = False, max_steps: Optional[int] = None,
                 max_step: Optional[float] = None, initial_step: Optional[float] = None,
                 min_step: Optional[float] = None, final_state: bool = True,
                 summary: bool = True, sample_at: Sequence[float] = (),
                 threads: Optional[int] = None) -> Table:
        """Many runs of this model, on ``threads`` threads (every core by default) with the
        interpreter released, one row per case in the order given.

        ``cases``: a DataFrame (or dict of arrays) whose columns are parameters and initial
        coordinates or speeds by name; or give ``parameters`` (the same, parameters only) and
        ``states`` (initial values by name, one state for all, or an array of one state per
        case). A case's state is built from its values as :meth:`state` does, with its
        parameters. The row keeps the values given, then ``final_<state>`` (``final_state``),
        the summary's figures (``summary``), each event's first time and count, and the state
        at the times ``sample_at``. A failed case is a row of NaN with its error
        (``Table.errors``); the others run on. Run settings as for :meth:`simulate`."""
        d = self._description
        params, named = _columns(parameters), []
        if cases is not None:
            for name, values in _columns(cases):
                if name in d["parameters"]:
                    params.append((name, values))
                elif name in d["coordinates"] or name in d["speeds"]:
                    named.append((name, values))
                else:
                    raise ValueError(
                        f"cases: the column {name!r} is neither a parameter nor a coordinate or "
                        f"speed of {d['name']}; parameters: {', '.join(d['parameters'])}; state: "
                        f"{', '.join(d['state'])}")
        if states is None:
            states_arg = named if named else np.zeros(len(d["state"]))
        elif isinstance(states, np.ndarray) or (isinstance(states, (list, tuple))
                                                 and not isinstance(states, dict)):
            if named:
                raise ValueError("states: initial values are given by name in `cases` already")
            states_arg = np.ascontiguousarray(np.asarray(states, dtype=float))
        else:
            states_arg = named + _columns(states)
        counts = {len(v) for _, v in params} | ({len(v) for _, v in states_arg}
                                                 if isinstance(states_arg, list) else set())
        if isinstance(states_arg, np.ndarray) and states_arg.ndim == 2:
            counts.add(states_arg.shape[0])
        if len(counts) > 1:
            raise ValueError(f"cases: columns of different lengths {sorted(counts)}")
        count = counts.pop() if counts else 1
        if isinstance(inputs, Lqr):
            inputs = inputs._native
        native = self._native.ensemble(
            count, params, states_arg, t0=t0, t_end=t_end, dt=dt, method=method, rtol=rtol,
            atol=atol, step=step, max_steps=max_steps, max_step=max_step,
            initial_step=initial_step, min_step=min_step, inputs=inputs,
            events=_event_specs(events) if events else None, lambdas=lambdas, project=project,
            final_state=final_state, summary=summary, sample_at=[float(t) for t in sample_at],
            threads=threads)
        return Table(native)

    # Analysis.

    def linearize(self, x, u=None, t: float = 0.0) -> Linearization:
        """The linearization δẋ = A δx + B δu at (t, x, u) (exact derivatives)."""
        return Linearization(self._native.linearize(x, u, t))

    def rhs(self, x, u=None, t: float = 0.0) -> np.ndarray:
        """The right-hand side ẋ = F(t, x, u)."""
        return self._native.rhs(x, u, t)

    def energy(self, x, t: float = 0.0) -> float:
        return self._native.energy(x, t)

    def constraint_forces(self, x, u=None, t: float = 0.0) -> np.ndarray:
        """The Lagrange multipliers λ, one per constraint."""
        return self._native.constraint_forces(x, u, t)

    def output_values(self, x, t: float = 0.0) -> np.ndarray:
        """The outputs y = h(t, x) of a model with ``#[outputs]``."""
        return self._native.outputs(x, t)

    def scene(self, run: Run, show: Optional[Sequence[str]] = None,
              title: Optional[str] = None, height: int = 520) -> Scene:
        """The run as a 3D scene (a model with bodies): shown inline in Jupyter, or
        ``.save("run.html")``. ``show``: the columns listed beside it."""
        page = self._native.scene(run._native, None if show is None else list(show), title)
        return Scene(page, height)

    def __repr__(self) -> str:
        values = ", ".join(f"{k}={v:g}" for k, v in self.parameters.items())
        return f"{type(self).__name__}({values})"

    def __eq__(self, other) -> bool:
        return (type(self) is type(other)
                and all(a == b or (math.isnan(a) and math.isnan(b))
                        for a, b in zip(self._native.parameter_values(),
                                        other._native.parameter_values())))

    __hash__ = None


def model_class(native_type, module: str = "hamel.models", doc: Optional[str] = None) -> type:
    """The Python class of a model type from an extension module."""
    description = dict(native_type.describe())
    name = description["name"]
    # The parameter struct's doc comment (`Parameters::DOC`), as rustdoc shows it.
    lines = [doc or description.get("doc") or f"The model {name}."]
    lines.append("\nParameters (keywords" + (", with their defaults" if description["defaults"] else "") + "):")
    defaults = description["defaults"] or [None] * len(description["parameters"])
    for p, text, default in zip(description["parameters"], description["parameter_docs"], defaults):
        lines.append(f"    {p}: {text}" + (f" [{default:g}]" if default is not None else ""))
    lines.append(f"\nState: {', '.join(description['state'])}")
    if description["inputs"]:
        lines.append(f"Inputs: {', '.join(description['inputs'])}")
    return type(name, (Model,), {"_native_type": native_type, "_description": description,
                                 "__module__": module, "__doc__": "\n".join(lines)})
