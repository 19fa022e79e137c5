"""Tables as pandas DataFrames (when pandas is installed) or dicts of NumPy arrays."""

from __future__ import annotations

import csv
import os
import re
from typing import Any, Optional

import numpy as np

from . import _native


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


#: Columns that hold counts, indices or flags (``pin``, ``step``, ``n``, ``n_samples``,
#: ``window``, ``segment_count``, ``frame_index``, a tool node's ``held`` …): integers, as int64
#: when every value is one. Other numeric columns stay float64 even where their values happen
#: to be whole (the library writes 150.0 N as ``150``; ``contact_particles`` is a mean over
#: the steps of a row), so a column's type does not depend on its data.
_INTEGER = re.compile(r"^(pin|step|n|segment|cycle|case|fold|frame|index|window|held|n_\w+|\w+_(count|index))$")


def _column(name: str, values: list) -> Any:
    if _INTEGER.match(name):
        try:
            return np.array([int(v) for v in values], dtype=np.int64)
        except ValueError:
            pass
    try:
        return np.array([float(v) if v != "" else np.nan for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=object)


def read_csv(path: "str | os.PathLike[str]", as_frame: Optional[bool] = None) -> Any:
    """A CSV with a header: count and index columns as int64 arrays, other numeric columns as
    float64 arrays, the rest as object arrays."""
    # greybox's one safe open: a regular file under the data cap (a FIFO, a device or a
    # directory refused, never waited on), a missing file MissingFileError (FileNotFoundError)
    text = _native.read_input(os.fspath(path), "table").decode("utf-8")
    lines = text.splitlines(keepends=True)
    rows = list(csv.reader(line for line in lines if not line.startswith("#")))
    if not rows:
        return table({}, as_frame)
    head, body = rows[0], rows[1:]
    cols = {name: _column(name, [r[i] if i < len(r) else "" for r in body]) for i, name in enumerate(head)}
    return table(cols, as_frame)
