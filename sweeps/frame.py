"""Rows as a pandas DataFrame, when pandas is installed (it is not a dependency of optraj).

>>> from optraj import sweeps
>>> frame = sweeps.read_table("map.parquet")   # doctest: +SKIP
>>> frame.groupby("status").size()             # doctest: +SKIP
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.sweeps.columns import COLUMNS
from optraj.sweeps.store import read_rows

__all__ = ["read_table", "to_frame"]


def to_frame(rows: Iterable[dict[str, object]]) -> Any:
    """A ``pandas.DataFrame`` of ``rows``, one column per entry of :data:`COLUMNS`, in order.

    Any other key of the rows follows, in the order met.

    Raises:
        MissingDependencyError: pandas is not installed.
    """
    try:
        pandas = importlib.import_module("pandas")
    except ImportError as exc:
        raise MissingDependencyError("pandas", "sweeps", "sweeps.to_frame") from exc
    found = list(rows)
    names = dict.fromkeys(COLUMNS)
    for row in found:
        names.update(dict.fromkeys(row))
    return pandas.DataFrame(found, columns=list(names))


def read_table(path: str | os.PathLike[str]) -> Any:
    """The rows a sweep kept at ``path`` (``.parquet`` or JSON-lines) as a DataFrame.

    A Parquet table is read with the rows of a journal a killed run left beside it.

    Raises:
        InvalidInputError: No file at ``path``.
        MissingDependencyError: pandas (or, for Parquet, pyarrow) is not installed.
    """
    file = Path(path)
    rows = read_rows(file)
    if not rows and not file.exists():
        raise InvalidInputError(
            f"no sweep table at {str(path)!r}: run a sweep with out={str(path)!r} first",
            name="path",
            value=str(path),
        )
    return to_frame(rows.values())
