"""Tables as pandas DataFrames (when pandas is installed) or dicts of NumPy arrays."""

from __future__ import annotations

import csv
import os
from typing import Any, Optional

import numpy as np


def _has_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def table(columns: dict, as_frame: Optional[bool] = None) -> Any:
    """``columns`` as a DataFrame (``as_frame`` True, or None with pandas installed) or as the
    dict itself."""
    if as_frame is None:
        as_frame = _has_pandas()
    if as_frame:
        import pandas as pd

        return pd.DataFrame(columns)
    return columns


def _column(values: list) -> Any:
    try:
        return np.array([float(v) if v != "" else np.nan for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=object)


def read_csv(path: "str | os.PathLike[str]", as_frame: Optional[bool] = None) -> Any:
    """A CSV with a header: numeric columns as float arrays, others as object arrays."""
    with open(os.fspath(path), newline="", encoding="utf-8") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    if not rows:
        return table({}, as_frame)
    head, body = rows[0], rows[1:]
    cols = {name: _column([r[i] if i < len(r) else "" for r in body]) for i, name in enumerate(head)}
    return table(cols, as_frame)
