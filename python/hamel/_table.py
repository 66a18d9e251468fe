"""An ensemble's or a study's table: one row per case, in case order."""

from __future__ import annotations

from typing import Dict, List, Optional, Tuple

import numpy as np


class Table:
    """Rows of cases: ``table["final_x"]`` a column (a read-only NumPy view), ``columns``,
    ``cases`` (each row's case index), ``errors`` (per row ``None`` or ``(kind, message)``),
    ``to_pandas()`` (with the columns ``error_kind`` and ``error``), ``to_arrow()``,
    ``to_csv()`` (the same bytes as Rust's ``Table::write_csv``)."""

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
        errors = self.errors
        columns: Dict[str, object] = {"case": self.cases}
        columns.update({name: self[name] for name in self.columns})
        columns["error_kind"] = [e[0] if e else None for e in errors]
        columns["error"] = [e[1] if e else None for e in errors]
        return columns

    def to_pandas(self):
        import pandas as pd

        return pd.DataFrame(self.to_dict())

    def to_arrow(self):
        import pyarrow as pa

        return pa.table(self.to_dict())

    def to_csv(self, path: Optional[str] = None) -> Optional[str]:
        if path is None:
            return self._native.csv()
        self._native.save_csv(str(path))
        return None

    def __repr__(self) -> str:
        return f"<hamel.Table: {len(self)} rows ({self.failed} failed), columns {', '.join(self.columns)}>"
