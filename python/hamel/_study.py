"""Studies from a DataFrame, with the tables, shards, manifests and merges of Rust's
``hamel::study``: the same files, byte for byte, whether a study's tasks run from Python or
from a Rust program."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Optional, Sequence, Union

from ._linear import Lqr
from ._model import Model, _columns, _event_specs
from ._table import Table


def study(model: Model, cases, *, name: str = "study", out: Optional[Union[str, os.PathLike]] = None,
          shard: Optional[str] = None, merge: Optional[Union[str, os.PathLike]] = None,
          into: Optional[Union[str, os.PathLike]] = None, format: str = "csv",
          threads: Optional[int] = None, t_end: float = 10.0, dt: float = 0.01,
          method: str = "dopri5", rtol: Optional[float] = None, atol: Optional[float] = None,
          t0: float = 0.0, step: Optional[float] = None, inputs=None, events: Sequence = (),
          lambdas: bool = False, project: bool = False, max_steps: Optional[int] = None,
          max_step: Optional[float] = None, initial_step: Optional[float] = None,
          min_step: Optional[float] = None, final_state: bool = True, summary: bool = True,
          sample_at: Sequence[float] = ()):
    """A study of ``model``: one run per row of ``cases`` (a DataFrame or a dict of arrays
    whose columns are parameters and initial coordinates or speeds by name), each row of the
    result its parameters and what the run gave (``final_<state>``, the summary's figures,
    each event's first time and count, the state at ``sample_at``), as in ``hamel::study``.

    * In memory (no ``out``, no ``merge``): returns the :class:`~hamel.Table`.
    * One task of a batch engine: ``out=DIR`` with ``shard="i/n"`` (or ``"env"``: the shard
      from Slurm's, PBS's or LSF's array variables) writes that shard's file and manifest into
      DIR (a shard already complete is skipped), as the Rust study's ``--table --out --shard``.
    * ``merge=DIR`` joins the finished shards into ``into`` (by default ``<name>.csv``), byte
      for byte the file one task running the whole table writes.

    Run settings as for :meth:`hamel.Model.simulate`; ``threads`` (default: every core)."""
    columns = _columns(cases)
    if not columns:
        raise ValueError("cases: a study needs a table with at least one column")
    lengths = {len(v) for _, v in columns}
    if len(lengths) != 1:
        raise ValueError(f"cases: columns of different lengths {sorted(lengths)}")
    names = [n for n, _ in columns]
    rows = [list(map(float, row)) for row in zip(*(v for _, v in columns))]
    if out is not None and merge is not None:
        raise ValueError("out and merge: a task writes its shard (out=), the merge joins them (merge=): give one")
    arguments = None
    if out is not None:
        arguments = ["--out", os.fspath(out)]
        if shard is not None:
            arguments += ["--shard", shard]
    elif merge is not None:
        arguments = ["--merge", os.fspath(merge)]
        if into is not None:
            arguments += ["--into", os.fspath(into)]
    elif shard is not None or into is not None:
        raise ValueError("shard and into go with out= (a task) and merge= (the merge)")
    if arguments is not None:
        arguments += ["--format", format]
        if threads is not None:
            arguments += ["--threads", str(threads)]
    if isinstance(inputs, Lqr):
        inputs = inputs._native
    with tempfile.TemporaryDirectory(prefix="hamel-study-") as scratch:
        table_path = str(Path(scratch) / "cases.csv")
        native = model._native.study(
            name, names, rows, arguments, table_path, t0=t0, t_end=t_end, dt=dt,
            method=method, rtol=rtol, atol=atol, step=step, max_steps=max_steps,
            max_step=max_step, initial_step=initial_step, min_step=min_step, inputs=inputs,
            events=_event_specs(events) if events else None, lambdas=lambdas, project=project,
            final_state=final_state, summary=summary, sample_at=[float(t) for t in sample_at],
            threads=threads)
    return None if native is None else Table(native)
