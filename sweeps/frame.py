"""Rows as a pandas DataFrame, when pandas is installed (it is not a dependency of optraj)."""

from __future__ import annotations

import importlib
from collections.abc import Iterable
from typing import Any

from optraj.errors import MissingDependencyError
from optraj.sweeps.columns import COLUMNS

__all__ = ["to_frame"]


def to_frame(rows: Iterable[dict[str, object]]) -> Any:
    """A ``pandas.DataFrame`` of ``rows``, one column per entry of :data:`COLUMNS`, in order.

    Raises:
        MissingDependencyError: pandas is not installed.
    """
    try:
        pandas = importlib.import_module("pandas")
    except ImportError as exc:
        raise MissingDependencyError("pandas", "sweeps", "sweeps.to_frame") from exc
    return pandas.DataFrame(list(rows), columns=list(COLUMNS))
