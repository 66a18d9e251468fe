"""hamel's errors as Python exceptions.

Every error hamel's Rust side reports is raised as an instance of a subclass of
:class:`hamel.Error`, one class per kind (the kind is ``Error.kind()`` in Rust, the
``error_kind`` column of a study's table). Each carries:

* ``kind``: the kind's stable name in snake case (``"step_size_underflow"``);
* ``message``: the same text as the Rust error's;
* ``time``: the time the error names, or ``None``;
* ``state``: the state (or configuration) it names, as a dict by name, or ``None``.

Kinds that are mistakes in what was asked (a parameter that is not finite, an unknown name,
a setting out of range) are also ``ValueError`` (``TypeError`` for an unknown parameter, as
for an unknown keyword), so ``except ValueError`` catches them too.

The classes live here, in Python, and every extension module of models — the catalogue, a
model from :func:`hamel.compile`, a crate's own — raises these same classes.
"""

from __future__ import annotations

from typing import Dict, Optional

__all__ = ["Error", "CompileError", "SceneError"]


class Error(Exception):
    """An error of hamel: see the module's documentation."""

    kind: str = "error"

    def __init__(self, message: str, kind: Optional[str] = None,
                 time: Optional[float] = None, state: Optional[Dict[str, float]] = None):
        super().__init__(message)
        self.message = message
        if kind is not None:
            self.kind = kind
        self.time = time
        self.state = state

    def __reduce__(self):
        return (type(self), (self.message, self.kind, self.time, self.state))


class CompileError(Error):
    """:func:`hamel.compile` could not build the model: ``message`` is rustc's, pointing at
    the lines of the source given (``diagnostics`` holds each of rustc's messages)."""

    kind = "compile"

    def __init__(self, message: str, diagnostics=(), path: Optional[str] = None):
        super().__init__(message)
        self.diagnostics = list(diagnostics)
        self.path = path

    def __reduce__(self):
        return (type(self), (self.message, self.diagnostics, self.path))


# Each kind of the Rust `Error` (`hamel-runtime/src/error_kind.rs`), with the built-in
# exception it also is, if any.
_KINDS = {
    "invalid_parameter": ValueError,
    "unknown_parameter": TypeError,
    "non_finite_initial_value": ValueError,
    "constraint_violation": ValueError,
    "singular_mass_matrix": None,
    "unbounded_inertia": None,
    "unphysical_body": ValueError,
    "impossible_geometry": ValueError,
    "singular_orientation": None,
    "singular_transformation": None,
    "inverse_mismatch": None,
    "step_size_underflow": None,
    "newton_not_converged": None,
    "singular_iteration_matrix": None,
    "span_too_short": ValueError,
    "too_many_steps": None,
    "non_finite_state": None,
    "non_finite_rate": None,
    "invalid_setting": ValueError,
    "too_many_samples": ValueError,
    "table": ValueError,
    "invalid_shard": ValueError,
    "case_panicked": None,
    "progress_panicked": None,
    "invalid_column_name": ValueError,
    "io": OSError,
    "read": OSError,
    "assembly": None,
    "holonomic_violation": ValueError,
    "inconsistent_model": None,
    "unknown_state_name": ValueError,
    "non_finite_operating_point": ValueError,
    "non_finite_argument": ValueError,
    "non_finite_input": None,
    "non_finite_derivative": None,
    "unknown_name": ValueError,
    "duplicate_name": ValueError,
    "dimension_mismatch": ValueError,
    "not_cyclic": None,
    "singular_elimination": None,
    "eigen_analysis": None,
    "ambiguous_state": ValueError,
    "root_not_bracketed": None,
    "non_finite_root_function": None,
    "root_not_found": None,
    "non_finite_event": None,
    "indefinite_mass_matrix": ValueError,
    "non_finite_dynamics": None,
    "relative_degree": None,
    "singular_decoupling": None,
    "no_stabilizing_solution": None,
    "invalid_weights": ValueError,
    "invalid_reference": ValueError,
    # Raised by the Python package itself: a Rust panic caught at the boundary (a bug), and a
    # scene that cannot be drawn.
    "panic": None,
    "scene": None,
}


def _class_name(kind: str) -> str:
    return "".join(part.capitalize() for part in kind.split("_"))


_BY_KIND: Dict[str, type] = {}
for _kind, _builtin in _KINDS.items():
    _bases = (Error,) if _builtin is None else (Error, _builtin)
    _name = _class_name(_kind)
    _cls = type(_name, _bases, {"kind": _kind, "__module__": __name__,
                                "__doc__": f"hamel's error of kind ``{_kind}``."})
    globals()[_name] = _cls
    _BY_KIND[_kind] = _cls
    __all__.append(_name)
SceneError = _BY_KIND["scene"]
Panic = _BY_KIND["panic"]
del _kind, _builtin, _bases, _name, _cls


def error_class(kind: str) -> type:
    """The class of the errors of ``kind`` (:class:`Error` for a kind of a case's own)."""
    return _BY_KIND.get(kind, Error)


def _from_rust(kind: str, message: str, time: Optional[float], state: Optional[dict]):
    """The exception for a Rust error (called by the extension modules)."""
    cls = _BY_KIND.get(kind, Error)
    return cls(message, kind, time, state)
