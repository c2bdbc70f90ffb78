from optraj import sweeps
from optraj.sweeps.columns import COLUMNS, OUTCOME_COLUMNS, STATUSES, empty_row


def test_every_column_has_a_unit_and_a_meaning():
    assert next(iter(COLUMNS)) == "shot_id"
    for unit, meaning in COLUMNS.values():
        assert isinstance(unit, str) and meaning
    assert COLUMNS["speed"][0] == "m/s" and COLUMNS["plan_time"][0] == "s"
    assert set(STATUSES) == {"planned", "refused", "failed", "timed out"}
    assert sweeps.COLUMNS is COLUMNS


def test_units_of_the_contact_and_outcome_columns():
    units = {name: unit for name, (unit, _) in COLUMNS.items()}
    assert units["max_speed"] == "m/s" and units["contact_search_time"] == "s"
    assert units["heading_error"] == "deg" and units["speed_error"] == "-"
    assert units["outcome_time"] == "s" and units["hit"] == units["on_target"] == ""
    assert list(COLUMNS)[-len(OUTCOME_COLUMNS) :] == list(OUTCOME_COLUMNS)
    assert sweeps.OUTCOME_COLUMNS is OUTCOME_COLUMNS
    assert list(COLUMNS)[:3] == ["shot_id", "robot", "kind"]


def test_empty_row_has_every_column_in_order():
    row = empty_row()
    assert list(row) == list(COLUMNS)
    assert set(row.values()) == {None}
    assert empty_row() is not row
