from optraj import sweeps
from optraj.sweeps.columns import COLUMNS, STATUSES, empty_row


def test_every_column_has_a_unit_and_a_meaning():
    assert next(iter(COLUMNS)) == "shot_id"
    for unit, meaning in COLUMNS.values():
        assert isinstance(unit, str) and meaning
    assert COLUMNS["speed"][0] == "m/s" and COLUMNS["plan_time"][0] == "s"
    assert set(STATUSES) == {"planned", "refused", "failed", "timed out"}
    assert sweeps.COLUMNS is COLUMNS


def test_empty_row_has_every_column_in_order():
    row = empty_row()
    assert list(row) == list(COLUMNS)
    assert set(row.values()) == {None}
    assert empty_row() is not row
