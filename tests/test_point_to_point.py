"""Tests of problems.point_to_point."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, JointLimitError
from problems import BoundaryState, PointToPoint


def test_defaults_are_rest_and_constraints_are_the_two_states():
    robot = get_robot("paddle4")
    problem = PointToPoint(robot, robot.home, [0.5, 0.1, 0.2, 0.0])
    np.testing.assert_array_equal(problem.qd_start, np.zeros(4))
    assert problem.qdd_start is None and problem.limits is robot.limits
    start, end = problem.constraints()
    assert isinstance(start, BoundaryState) and start.at == "start" and end.at == "end"
    np.testing.assert_array_equal(end.q, [0.5, 0.1, 0.2, 0.0])


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"q_goal": [0.5, 0.0, 1.2, 0.0]}, JointLimitError, r"q_goal: joint 'J3' position 1.2 m"),
        (
            {"qd_start": [0.0, 5.0, 0.0, 0.0]},
            JointLimitError,
            r"'J2' velocity 5 rad/s .* \[-3, 3\]",
        ),
        ({"qdd_goal": [9.0, 0, 0, 0]}, JointLimitError, r"'J1' acceleration 9 m/s\^2"),
        ({"q_goal": [0.5, np.nan, 0, 0]}, InvalidInputError, "finite"),
        ({"q_goal": [0.5, 0.0]}, InvalidInputError, r"shape \(4,\)"),
        ({"duration": 0.0}, InvalidInputError, "duration must be > 0 s"),
        ({"tolerance": -1.0}, InvalidInputError, "tolerance must be >= 0, got -1"),
        ({"tolerance": True}, InvalidInputError, "tolerance must be a numeric"),
        ({"robot": "paddle4"}, InvalidInputError, "robots.Robot"),
    ],
)
def test_bad_values_name_the_value_and_the_bound(kwargs, error, match):
    robot = get_robot("paddle4")
    fields = {"robot": robot, "q_start": robot.home, "q_goal": robot.home}
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        PointToPoint(**fields)


def test_limits_must_match_the_robot():
    with pytest.raises(InvalidInputError, match=r"limits must be a robots\.JointLimits"):
        PointToPoint(
            get_robot("paddle4"), np.zeros(4), np.zeros(4), limits=get_robot("youbot").limits
        )
