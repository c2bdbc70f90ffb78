"""Rows as a typed Parquet table: one arrow type per column, written atomically.

The schema follows :data:`optraj.sweeps.COLUMNS` at run time, in its order, then any other
key of the rows in the order met. A column's arrow type is, first, its entry in
:data:`ARROW_TYPES`; else what its values are (all bools: ``bool``, all integers: ``int64``,
all numbers: ``float64``, all strings: ``string``); else, for a column of Nones,
``float64`` when :data:`COLUMNS` gives it a unit and ``string`` otherwise. Each field
carries its unit and meaning as metadata. pyarrow comes with the ``sweeps`` extra.

>>> from optraj import sweeps
>>> sweeps.write_parquet(rows, "map.parquet")     # doctest: +SKIP
>>> sweeps.read_parquet("map.parquet") == rows   # doctest: +SKIP
True
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.sweeps.columns import COLUMNS

__all__ = [
    "ARROW_TYPES",
    "arrow_type",
    "pyarrow",
    "read_parquet",
    "to_arrow",
    "write_parquet",
]

#: Arrow type names of the columns whose values alone would not say it (a column of Nones
#: still gets its type); the other columns follow the rules of the module docstring.
ARROW_TYPES: dict[str, str] = {
    "shot_id": "string",
    "robot": "string",
    "planner": "string",
    "status": "string",
    "error_type": "string",
    "error_message": "string",
    "binding_joint": "string",
    "binding_quantity": "string",
    "kind": "string",
    "iterations": "int64",
    "check_ok": "bool",
    "hit": "bool",
    "on_target": "bool",
}


def pyarrow() -> Any:
    """The ``pyarrow`` module, or a typed error naming the extra that installs it.

    Raises:
        MissingDependencyError: pyarrow is not installed.
    """
    try:
        return importlib.import_module("pyarrow")
    except ImportError as exc:
        raise MissingDependencyError("pyarrow", "sweeps", "Parquet sweep tables") from exc


def _parquet() -> Any:
    pyarrow()  # the typed error when pyarrow is missing
    return importlib.import_module("pyarrow.parquet")


def _inferred(values: list[object]) -> str | None:
    """The arrow type name all the non-None ``values`` share, or None when there are none."""
    found = [value for value in values if value is not None]
    if not found:
        return None
    if all(isinstance(value, bool) for value in found):
        return "bool"
    if all(isinstance(value, int) and not isinstance(value, bool) for value in found):
        return "int64"
    if all(isinstance(value, (int, float)) and not isinstance(value, bool) for value in found):
        return "float64"
    if all(isinstance(value, str) for value in found):
        return "string"
    return "infer"  # a mix: left to pyarrow, which refuses what cannot be one column


def arrow_type(name: str, values: Iterable[object] = ()) -> str:
    """The arrow type name of column ``name`` holding ``values`` (module docstring rules).

    Returns:
        ``"string"``, ``"float64"``, ``"int64"``, ``"bool"`` or ``"infer"`` (pyarrow's choice,
        for a column of mixed values that is not in :data:`COLUMNS`).
    """
    if name in ARROW_TYPES:
        return ARROW_TYPES[name]
    found = _inferred(list(values))
    if found is not None:
        return found
    unit = COLUMNS.get(name, ("", ""))[0]
    return "float64" if unit else "string"


def _names(rows: list[dict[str, object]]) -> list[str]:
    """The columns: every entry of COLUMNS, then the rows' other keys in the order met."""
    names = dict.fromkeys(COLUMNS)
    for row in rows:
        names.update(dict.fromkeys(row))
    return list(names)


def _column(name: str, values: list[object]) -> Any:
    """One arrow array and its field, with the unit and meaning as field metadata."""
    pa = pyarrow()
    kind = arrow_type(name, values)
    try:
        array = (
            pa.array(values) if kind == "infer" else pa.array(values, type=pa.type_for_alias(kind))
        )
    except (pa.ArrowInvalid, pa.ArrowTypeError, OverflowError) as exc:
        bad = next((v for v in values if v is not None), None)
        raise InvalidInputError(
            f"column {name!r} must hold {kind} values or None, got {bad!r}: {exc}",
            name=name,
            value=bad,
        ) from exc
    unit, meaning = COLUMNS.get(name, ("", ""))
    field = pa.field(name, array.type, metadata={"unit": unit, "meaning": meaning})
    return array, field


def to_arrow(rows: Iterable[dict[str, object]]) -> Any:
    """A ``pyarrow.Table`` of ``rows`` with the typed schema; a missing key is None."""
    pa = pyarrow()
    found = list(rows)
    arrays, fields = [], []
    for name in _names(found):
        array, field = _column(name, [row.get(name) for row in found])
        arrays.append(array)
        fields.append(field)
    return pa.Table.from_arrays(arrays, schema=pa.schema(fields))


def write_parquet(rows: Iterable[dict[str, object]], path: str | os.PathLike[str]) -> Path:
    """Write ``rows`` to the Parquet file ``path`` atomically; returns the path.

    The table is written to a temporary file in the same folder, flushed to disk and moved
    over ``path`` in one step, so a reader sees the old file or the new one, never half.

    Raises:
        InvalidInputError: A column whose values do not fit its type.
        MissingDependencyError: pyarrow is not installed.
        OSError: The folder cannot be written.
    """
    parquet = _parquet()
    target = Path(path)
    data = to_arrow(rows)
    temporary = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        with temporary.open("wb") as file:
            parquet.write_table(data, file)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)
    return target


def read_parquet(path: str | os.PathLike[str]) -> list[dict[str, object]]:
    """The rows of the Parquet file ``path``, each a dict in the file's column order.

    Raises:
        InvalidInputError: ``path`` is not a Parquet file.
        MissingDependencyError: pyarrow is not installed.
        OSError: ``path`` cannot be read.
    """
    parquet = _parquet()
    pa = pyarrow()
    try:
        data = parquet.read_table(Path(path))
    except pa.ArrowInvalid as exc:
        raise InvalidInputError(
            f"{str(path)!r} is not a readable Parquet file: {exc}", name="path", value=str(path)
        ) from exc
    rows: list[dict[str, object]] = data.to_pylist()
    return rows
