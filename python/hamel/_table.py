"""An ensemble's or a study's table: one row per case, in case order."""

from __future__ import annotations

from typing import Dict, List, Optional, Tuple

import numpy as np


class Table:
    """Rows of cases: ``table["final_x"]`` a column (a read-only NumPy view), ``columns``,
    ``cases`` (each row's case index), ``errors`` (per row ``None`` or ``(kind, message)``),
    ``to_pandas()`` and ``to_arrow()`` (first the column ``case_index``, last ``error_kind``
    and ``error``), ``to_csv()`` (the same bytes as Rust's ``Table::write_csv``; with a path,
    written whole with its ``.manifest`` beside it, as Rust's ``Table::save_csv``).

    A failed case keeps its row: its given values, and NaN in memory for what its run could
    not compute, which the CSV leaves empty, Arrow makes null and pandas reads as missing, so
    that means and counts skip failed cases, as DuckDB's and polars' do on Rust's files."""

    def __init__(self, native):
        self._native = native

    @property
    def columns(self) -> Tuple[str, ...]:
        return tuple(self._native.names())

    def __getitem__(self, name: str) -> np.ndarray:
        return self._native.column(name)

    def __len__(self) -> int:
        return len(self._native)

    @property
    def cases(self) -> np.ndarray:
        return self._native.cases()

    @property
    def errors(self) -> List[Optional[Tuple[str, str]]]:
        return self._native.errors()

    @property
    def failed(self) -> int:
        return self._native.failed()

    def to_dict(self) -> Dict[str, object]:
        """The columns by name: ``case_index``, the table's columns (NumPy arrays, NaN where a
        failed case has no value), ``error_kind`` and ``error`` (``None`` for a case that
        succeeded)."""
        errors = self.errors
        columns: Dict[str, object] = {"case_index": self.cases}
        columns.update({name: self[name] for name in self.columns})
        columns["error_kind"] = [e[0] if e else None for e in errors]
        columns["error"] = [e[1] if e else None for e in errors]
        return columns

    def to_pandas(self):
        import pandas as pd

        return pd.DataFrame(self.to_dict())

    def to_arrow(self):
        """A ``pyarrow.Table``: the values of failed cases that their runs could not compute
        are null (as in Rust's Parquet files), not NaN."""
        import pyarrow as pa

        failed = np.array([e is not None for e in self.errors], dtype=bool)
        columns = {}
        for name, values in self.to_dict().items():
            if isinstance(values, np.ndarray) and values.dtype.kind == "f" and failed.any():
                columns[name] = pa.array(values, mask=failed & np.isnan(values))
            else:
                columns[name] = values
        return pa.table(columns)

    def to_csv(self, path: Optional[str] = None) -> Optional[str]:
        if path is None:
            return self._native.csv()
        self._native.save_csv(str(path))
        return None

    def __repr__(self) -> str:
        return f"<hamel.Table: {len(self)} rows ({self.failed} failed), columns {', '.join(self.columns)}>"
