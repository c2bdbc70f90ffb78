import importlib.util

import pytest

from optraj.errors import MissingDependencyError
from optraj.sweeps import COLUMNS, to_frame
from optraj.sweeps.columns import empty_row

HAVE_PANDAS = importlib.util.find_spec("pandas") is not None


@pytest.mark.skipif(HAVE_PANDAS, reason="pandas is installed")
def test_without_pandas_the_error_names_the_package():
    with pytest.raises(MissingDependencyError, match="pandas") as info:
        to_frame([empty_row()])
    assert info.value.package == "pandas"


@pytest.mark.skipif(not HAVE_PANDAS, reason="needs pandas")
def test_frame_has_every_column_in_order():
    frame = to_frame([empty_row() | {"shot_id": "a"}])
    assert list(frame.columns) == list(COLUMNS) and frame["shot_id"].tolist() == ["a"]
