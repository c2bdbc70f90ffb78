"""Tests of sweeps.maps: rows arranged per heading over the ball positions."""

import math

import numpy as np
import pytest
from sweeps_support import HEADINGS, XS, YS, grid_rows, made_up_value, random_rows

from optraj.errors import InvalidInputError
from optraj.sweeps.columns import empty_row
from optraj.sweeps.maps import MAX_PANELS, heading_maps, rows_of, speeds_of


def test_a_grid_gives_one_map_per_heading_with_values_at_their_cells():
    maps = heading_maps(grid_rows(), "motion_time", speed=0.3, one_per_point=True)
    assert [m.heading for m in maps] == list(HEADINGS) and all(m.on_grid for m in maps)
    for one in maps:
        np.testing.assert_allclose(one.x, XS, rtol=0, atol=1e-12)
        np.testing.assert_allclose(one.y, YS, rtol=0, atol=1e-12)
        assert one.values.shape == (len(YS), len(XS))
        for i, x in enumerate(XS):
            for j, y in enumerate(YS):
                assert one.values[j, i] == made_up_value(x, y, one.heading, 0.3)


def test_a_cell_takes_the_largest_value_of_its_speeds_and_nan_without_one():
    (one,) = heading_maps(grid_rows(), "max_speed", headings=[45.0])
    assert one.heading == 45.0
    assert one.values[1, 0] == made_up_value(0.7, 0.1, 45.0, 0.9)
    assert np.isnan(one.values[:, 2]).all()  # x = 0.9 m gave no max_speed
    (refused,) = heading_maps(grid_rows(), "motion_time", speed=0.9, headings=[0.0])
    assert np.isnan(refused.values).all()


def test_a_random_set_is_one_panel_of_points():
    rows = random_rows(MAX_PANELS + 4, seed=5)
    (one,) = heading_maps(rows, "motion_time", one_per_point=True)
    assert one.heading is None and not one.on_grid
    assert sorted(one.values.tolist()) == [float(i) for i in range(len(rows))]
    index = one.values.tolist().index(3.0)
    assert (one.x[index], one.y[index]) == (
        round(rows[3]["ball_x"], 4),
        round(rows[3]["ball_y"], 4),
    )


def test_a_dataframe_is_read_as_its_rows():
    pandas = pytest.importorskip("pandas")
    rows = grid_rows()
    frame = pandas.DataFrame(rows)
    assert rows_of(frame)[0]["ball_x"] == 0.7 and math.isnan(rows_of(frame)[1]["motion_time"])
    np.testing.assert_array_equal(
        heading_maps(frame, "max_speed")[0].values, heading_maps(rows, "max_speed")[0].values
    )
    assert speeds_of(rows) == [0.3, 0.9]


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: heading_maps([], "max_speed"), "at least one sweep row, got none"),
        (lambda: heading_maps({"a": 1}, "max_speed"), "rows must be sweep rows"),
        (lambda: heading_maps([{"ball_x": 0.7}], "max_speed"), "lacks the column 'ball_y'"),
        (lambda: heading_maps(grid_rows(), "nope"), "no column 'nope'"),
        (lambda: heading_maps([empty_row() | {"ball_x": 0.7, "ball_y": 0.1, "heading": "x"}],
                              "max_speed"), "rows[0]['heading'] must be a number, got 'x'"),
        (lambda: heading_maps(grid_rows(), "motion_time", speed=0.7),
         "speed 0.7 m/s is not in the rows; their speeds: 0.3, 0.9 m/s"),
        (lambda: heading_maps(grid_rows(), "motion_time", speed=-1.0), "speed must be > 0 m/s"),
        (lambda: heading_maps(grid_rows(), "max_speed", headings=[30.0]),
         "heading 30 deg is not in the rows; their headings: 0, 45 deg"),
        (lambda: heading_maps(grid_rows(), "max_speed", headings=[]), "at least one heading"),
        (lambda: heading_maps(grid_rows(), "motion_time", one_per_point=True),
         "several speeds (0.3, 0.9 m/s) at one ball position: choose one with speed="),
    ],
)  # fmt: skip
def test_bad_input_raises_typed_errors_naming_themade_up_value(call, words):
    with pytest.raises(InvalidInputError) as info:
        call()
    assert words in str(info.value)
