"""Tests of sweeps.frame: rows as a pandas DataFrame, or a typed error without pandas."""

import math
import sys

import pytest

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.sweeps import COLUMNS, read_table, to_frame
from optraj.sweeps.columns import empty_row
from optraj.sweeps.store import RowFile


def test_without_pandas_the_error_names_the_package_and_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now fails
    with pytest.raises(MissingDependencyError, match=r"optraj\[sweeps\]") as info:
        to_frame([empty_row()])
    assert info.value.package == "pandas"


def test_frame_has_every_column_in_order():
    pytest.importorskip("pandas")  # installed by the sweeps extra, which make test installs
    frame = to_frame([empty_row() | {"shot_id": "a"}])
    assert list(frame.columns) == list(COLUMNS) and frame["shot_id"].tolist() == ["a"]


def test_extra_keys_follow_the_columns():
    pytest.importorskip("pandas")
    frame = to_frame([empty_row() | {"shot_id": "a", "extra": 1}, {"shot_id": "b", "more": "x"}])
    assert list(frame.columns) == [*COLUMNS, "extra", "more"]
    assert frame["shot_id"].tolist() == ["a", "b"]


@pytest.mark.parametrize("name", ["m.jsonl", "m.parquet"])
def test_read_table_reads_a_sweep_table(tmp_path, name):
    pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    rows = [empty_row() | {"shot_id": "a", "motion_time": 1.5}, empty_row() | {"shot_id": "b"}]
    with RowFile(tmp_path / name) as file:
        for row in rows:
            file.write(row)
    frame = read_table(tmp_path / name)
    assert list(frame.columns) == list(COLUMNS) and frame["shot_id"].tolist() == ["a", "b"]
    assert frame["motion_time"].iloc[0] == 1.5 and math.isnan(frame["motion_time"].iloc[1])


def test_read_table_of_a_missing_file_names_it(tmp_path):
    with pytest.raises(InvalidInputError, match=r"no sweep table at '.*nope\.parquet'"):
        read_table(tmp_path / "nope.parquet")
