"""Tests of sweeps.parquet: typed tables of rows, written atomically, read back equal."""

import sys

import pytest

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.sweeps import COLUMNS, read_parquet, write_parquet
from optraj.sweeps.columns import empty_row
from optraj.sweeps.parquet import ARROW_TYPES, arrow_type, to_arrow

pa = pytest.importorskip("pyarrow")  # installed by the sweeps extra, which make test installs


def _row(shot_id, **values):
    return empty_row() | {"shot_id": shot_id} | values


def test_types_come_from_the_table_then_the_values_then_the_unit():
    assert arrow_type("iterations") == "int64" and arrow_type("check_ok") == "bool"
    assert arrow_type("shot_id") == "string"
    assert arrow_type("motion_time") == "float64"  # a unit, no value: a float
    assert arrow_type("new_flag", [None, True, False]) == "bool"
    assert arrow_type("new_count", [3, None, 4]) == "int64"
    assert arrow_type("new_value", [3, 0.5]) == "float64"
    assert arrow_type("new_name", ["a", None]) == "string"
    assert arrow_type("new_empty", [None]) == "string"
    assert arrow_type("new_mix", [1, "a"]) == "infer"
    assert set(ARROW_TYPES.values()) <= {"string", "int64", "bool", "float64"}


def test_schema_follows_columns_in_order_with_units_and_extras_last():
    rows = [_row("a", motion_time=1.5, iterations=7, check_ok=True), _row("b") | {"extra": 2}]
    table = to_arrow(rows)
    assert table.column_names == [*COLUMNS, "extra"]
    types = dict(zip(table.column_names, table.schema.types, strict=True))
    assert types["motion_time"] == pa.float64() and types["iterations"] == pa.int64()
    assert types["check_ok"] == pa.bool_() and types["shot_id"] == pa.string()
    assert types["max_speed"] == pa.float64()  # all None, typed by its unit
    assert types["extra"] == pa.int64()
    assert table.schema.field("speed").metadata[b"unit"] == b"m/s"


def test_rows_read_back_equal_and_no_temporary_file_is_left(tmp_path):
    rows = [
        _row("a", ball_x=0.7, speed=0.3, status="planned", motion_time=2.25, check_ok=False),
        _row("b", status="refused", error_message="too fast", max_speed=1.25, iterations=3),
    ]
    path = write_parquet(rows, tmp_path / "m.parquet")
    assert read_parquet(path) == rows
    assert [p.name for p in tmp_path.iterdir()] == ["m.parquet"]
    write_parquet(rows[:1], path)  # replaced, not appended to
    assert read_parquet(path) == rows[:1]


def test_a_failed_write_leaves_the_old_table(tmp_path):
    path = write_parquet([_row("a")], tmp_path / "m.parquet")
    with pytest.raises(InvalidInputError, match=r"column 'iterations' must hold int64 .*'many'"):
        write_parquet([_row("b", iterations="many")], path)
    assert [row["shot_id"] for row in read_parquet(path)] == ["a"]
    assert [p.name for p in tmp_path.iterdir()] == ["m.parquet"]


def test_a_file_that_is_not_parquet_is_a_typed_error(tmp_path):
    path = tmp_path / "m.parquet"
    path.write_text('{"shot_id": "a"}\n')
    with pytest.raises(InvalidInputError, match="is not a readable Parquet file"):
        read_parquet(path)


def test_without_pyarrow_the_error_names_the_package_and_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow now fails
    with pytest.raises(MissingDependencyError, match=r"optraj\[sweeps\]") as info:
        write_parquet([_row("a")], tmp_path / "m.parquet")
    assert info.value.package == "pyarrow"
    assert list(tmp_path.iterdir()) == []
