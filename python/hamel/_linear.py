"""Linearizations (:class:`Linearization`: A and B as NumPy arrays, eigenvalues, modes with
their states named) and LQR designs (:class:`Lqr`, which a run takes as its inputs)."""

from __future__ import annotations

from typing import Dict, List, NamedTuple, Sequence, Union

import numpy as np


class Mode(NamedTuple):
    """A mode: an eigenvalue λ of A (the mode evolves as e^{λt}) and its eigenvector by
    state name, scaled so that its largest component is 1."""

    value: complex
    vector: Dict[str, complex]

    @property
    def dominant(self) -> str:
        """The state whose component is largest."""
        return max(self.vector, key=lambda name: abs(self.vector[name]))

    @property
    def stable(self) -> bool:
        return self.value.real < 0

    def __repr__(self) -> str:
        return f"Mode({self.value:.6g}, dominant {self.dominant!r})"


def _weight(w, names: Sequence[str], which: str) -> np.ndarray:
    """A weight matrix: an array, a number (times the identity) or a dict of diagonal
    entries by name (the others zero)."""
    n = len(names)
    if isinstance(w, dict):
        unknown = [k for k in w if k not in names]
        if unknown:
            raise ValueError(f"{which}: unknown name {unknown[0]!r}; the names are {', '.join(names)}")
        return np.diag([float(w.get(name, 0.0)) for name in names])
    if np.isscalar(w):
        return float(w) * np.eye(n)
    return np.ascontiguousarray(w, dtype=float)


class Linearization:
    """δẋ = A δx + B δu at an operating point: ``A``, ``B`` (NumPy arrays), ``states`` and
    ``inputs`` (their rows and columns), ``eigenvalues``, ``modes``."""

    def __init__(self, native):
        self._native = native

    @property
    def A(self) -> np.ndarray:
        return self._native.a()

    @property
    def B(self) -> np.ndarray:
        return self._native.b()

    @property
    def states(self) -> List[str]:
        return self._native.states()

    @property
    def inputs(self) -> List[str]:
        return self._native.inputs()

    @property
    def eigenvalues(self) -> np.ndarray:
        return self._native.eigenvalues()

    @property
    def modes(self) -> List[Mode]:
        return [Mode(value, dict(vector)) for value, vector in self._native.modes()]

    @property
    def operating_point(self):
        """``(t, state, inputs)``, the state and inputs as dicts by name."""
        return self._native.operating_point()

    def reduce(self, *keep: str) -> "Linearization":
        """The linearization on the states ``keep`` (cyclic coordinates dropped, dependent
        ones eliminated through the holonomic constraints)."""
        return Linearization(self._native.reduce(list(_names(keep))))

    def with_inputs(self, *keep: str) -> "Linearization":
        """The linearization with only the inputs ``keep``."""
        return Linearization(self._native.with_inputs(list(_names(keep))))

    def lqr(self, Q, R) -> "Lqr":
        """The linear-quadratic regulator with state weight ``Q`` and input weight ``R``
        (arrays, numbers times the identity, or dicts of diagonal entries by name)."""
        q = _weight(Q, self.states, "Q")
        r = _weight(R, self.inputs, "R")
        if q.ndim != 2 or r.ndim != 2:
            raise ValueError("Q and R must be square matrices (or numbers, or dicts by name)")
        return Lqr(self._native.lqr(q, r))

    def __str__(self) -> str:
        return self._native.text()

    def __repr__(self) -> str:
        return f"<hamel.Linearization: {len(self.states)} states, {len(self.inputs)} inputs>"


def _names(keep) -> Sequence[str]:
    if len(keep) == 1 and not isinstance(keep[0], str):
        return list(keep[0])
    return list(keep)


class Lqr:
    """An LQR design: the gain ``K`` (δu = −K δx), the Riccati solution ``P``, the closed
    loop's eigenvalues. Give it to a run as its inputs, ``model.simulate(x0, inputs=lqr)``:
    the feedback u = u₀ − K (x − x₀) is then evaluated in Rust."""

    def __init__(self, native):
        self._native = native

    @property
    def K(self) -> np.ndarray:
        return self._native.gain()

    @property
    def P(self) -> np.ndarray:
        return self._native.solution()

    @property
    def closed_loop_eigenvalues(self) -> np.ndarray:
        return self._native.closed_loop_eigenvalues()

    @property
    def residual(self) -> float:
        return self._native.residual()

    @property
    def states(self) -> List[str]:
        return self._native.states()

    @property
    def inputs(self) -> List[str]:
        return self._native.inputs()

    def __repr__(self) -> str:
        return f"<hamel.Lqr: K {self.K.shape[0]}×{self.K.shape[1]} over {', '.join(self.states)}>"


Weight = Union[np.ndarray, float, Dict[str, float]]
