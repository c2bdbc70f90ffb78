"""Tests of sweeps.frame: rows as a pandas DataFrame, or a typed error without pandas."""

import sys

import pytest

from optraj.errors import MissingDependencyError
from optraj.sweeps import COLUMNS, to_frame
from optraj.sweeps.columns import empty_row


def test_without_pandas_the_error_names_the_package_and_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now fails
    with pytest.raises(MissingDependencyError, match=r"optraj\[sweeps\]") as info:
        to_frame([empty_row()])
    assert info.value.package == "pandas"


def test_frame_has_every_column_in_order():
    pytest.importorskip("pandas")  # installed by the sweeps extra, which make test installs
    frame = to_frame([empty_row() | {"shot_id": "a"}])
    assert list(frame.columns) == list(COLUMNS) and frame["shot_id"].tolist() == ["a"]
