"""A run's results: :class:`Run` (columns as NumPy arrays, its summary, events, pandas and
Arrow), :class:`Summary` and :class:`EventRecord`."""

from __future__ import annotations

from typing import Dict, List, NamedTuple, Optional

import numpy as np


class EventRecord(NamedTuple):
    """An event that happened in a run: its name, time, the state then, and whether it ended
    the run."""

    name: str
    t: float
    state: Dict[str, float]
    terminal: bool


class Summary(dict):
    """What a run cost and how well it kept its invariants (``steps``, ``rejected``,
    ``evaluations``, ``samples``, ``max_constraint_residual``, ``initial_energy``,
    ``energy_error``, ``stopped``, ...); ``str(summary)`` is the summary as Rust prints it."""

    def __init__(self, values: dict, text: str):
        super().__init__(values)
        self._text = text

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __str__(self) -> str:
        return self._text


class Run:
    """A finished run of a model. ``run.t`` is the sample times, ``run["x"]`` any column
    (read-only NumPy arrays that view the run's memory: no copy); ``run.columns`` their
    names: ``t``, the state, the inputs, the energy, and (for a forced model) the energy
    balance, then constraint forces ``lambda_<constraint>`` if asked."""

    __slots__ = ("_native", "model", "_columns")

    def __init__(self, native, model=None):
        self._native = native
        self.model = model
        self._columns = None

    @property
    def columns(self) -> tuple:
        if self._columns is None:
            self._columns = tuple(self._native.names())
        return self._columns

    @property
    def t(self) -> np.ndarray:
        return self._native.column("t")

    def __getitem__(self, name: str) -> np.ndarray:
        return self._native.column(name)

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def __len__(self) -> int:
        return len(self._native)

    @property
    def summary(self) -> Summary:
        return Summary(self._native.summary(), self._native.summary_text())

    @property
    def events(self) -> List[EventRecord]:
        return [EventRecord(*e) for e in self._native.events()]

    def event_times(self, name: str) -> np.ndarray:
        """The times of the events called ``name``."""
        return np.array([e.t for e in self.events if e.name == name])

    @property
    def final(self) -> Dict[str, float]:
        """The last sample, by column."""
        return {name: float(self[name][-1]) for name in self.columns}

    def to_numpy(self) -> np.ndarray:
        """The samples as a (samples × columns) array (a copy)."""
        return np.column_stack([self[name] for name in self.columns])

    def to_dict(self) -> Dict[str, np.ndarray]:
        return {name: self[name] for name in self.columns}

    def to_pandas(self):
        """A ``pandas.DataFrame``, one column per column of the run."""
        import pandas as pd

        return pd.DataFrame(self.to_dict(), copy=False)

    def to_arrow(self):
        """A ``pyarrow.Table`` (polars reads it with ``polars.from_arrow``)."""
        import pyarrow as pa

        return pa.table(self.to_dict())

    def to_csv(self, path: Optional[str] = None) -> Optional[str]:
        """The run as CSV, the same bytes as Rust's ``Trajectory::write_csv`` (numbers in
        their shortest exact form); written to ``path``, or returned."""
        text = self._native.csv()
        if path is None:
            return text
        with open(path, "w", newline="") as f:
            f.write(text)
        return None

    def __repr__(self) -> str:
        t = self.t
        span = f", t = {t[0]:g} … {t[-1]:g}" if len(t) else ""
        name = type(self.model).__name__ if self.model is not None else "a model"
        return f"<hamel.Run of {name}: {len(t)} samples{span}, columns {', '.join(self.columns)}>"
