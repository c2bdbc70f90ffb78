"""Tests of planners.ocp.parameters."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.planners.ocp.parameters import ParameterLayout

LAYOUT = ParameterLayout((("time_scale", 1), ("entry", 3), ("speed", 1)))


def test_layout_vector_names_what_is_wrong():
    assert LAYOUT.vector().size == LAYOUT.size == sum(size for _, size in LAYOUT.entries)
    np.testing.assert_array_equal(LAYOUT.vector(), [1.0, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="speed"):
        LAYOUT.vector(speed=[1.0, 2.0])
    with pytest.raises(UnknownNameError, match="unknown NLP parameter 'velocity'"):
        LAYOUT.vector(velocity=1.0)
    for bad in (True, "1.0", np.nan):  # no bool, string or NaN posing as a speed
        with pytest.raises(InvalidInputError, match="speed"):
            LAYOUT.vector(speed=bad)


def test_values_go_in_and_come_out_by_name():
    p = LAYOUT.vector(speed=1.2, entry=[0.1, 0.2, 0.3])
    np.testing.assert_array_equal(LAYOUT.value(p, "speed"), [1.2])
    np.testing.assert_array_equal(LAYOUT.value(p, "entry"), [0.1, 0.2, 0.3])
    assert LAYOUT.names == ("time_scale", "entry", "speed")
    with pytest.raises(UnknownNameError, match="offset"):
        LAYOUT.value(p, "offset")
    with pytest.raises(InvalidInputError, match="'speed' is given twice"):
        ParameterLayout((("speed", 1), ("speed", 1)))


def test_a_pool_nlp_reads_its_strike_line_by_name():
    problem = problems.sawyer_pool_shot(1.0)
    built = OptimalControl("time").build(problem)
    names = built.compiled.parameters.names
    clearance = (
        "clearance_floor",
        "clearance_reach",
        "clearance_cushion",
        "clearance_extra",
        "clearance_apart",
        "clearance_ball",
        "clearance_direction",
        "clearance_behind",
    )
    assert names == ("time_scale", "entry", "direction", "e1", "e2", "speed", *clearance, "torque")
    np.testing.assert_array_equal(built.parameter("entry"), problem.entry_point)
    np.testing.assert_array_equal(built.parameter("direction"), problem.direction)
    assert built.parameter("speed").tolist() == [1.0]
    assert built.parameter("time_scale")[0] == pytest.approx(sum(g.guess for g in built.grids))
