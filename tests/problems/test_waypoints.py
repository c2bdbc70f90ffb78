"""Tests of problems.waypoints."""

from __future__ import annotations

import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, JointLimitError
from optraj.problems import BoundaryState, ViaPoint, Waypoints


def test_constraints_include_via_points_only_with_a_tolerance():
    robot = get_robot("paddle4")
    points = [robot.home, [0.5, 0.2, 0.3, 0.1], [0.6, 0.0, 0.1, 0.0]]
    loose = Waypoints(robot, points)
    assert [type(c) for c in loose.constraints()] == [BoundaryState, BoundaryState]
    exact = Waypoints(robot, points, via_tolerance=1e-6)
    kinds = [type(c) for c in exact.constraints()]
    assert kinds == [BoundaryState, ViaPoint, BoundaryState]
    assert exact.constraints()[1].index == 1


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"waypoints": [[0.45, 0, 0, 0]]}, InvalidInputError, "at least 2"),
        ({"waypoints": [[0.45, 0, 0, 0], [0.45, 0, 2.0, 0]]}, JointLimitError, "waypoint 1"),
        (
            {"segment_durations": [0.0]},
            InvalidInputError,
            r"segment_durations\[0\] must be >= 1e-06 s, got 0 s",
        ),
        ({"segment_durations": [1.0, 1.0]}, InvalidInputError, r"shape \(1,\)"),
        (
            {"segment_durations": [1e200]},
            InvalidInputError,
            r"segment_durations\[0\] must be <= 86400 s",
        ),
        ({"via_tolerance": -1.0}, InvalidInputError, "via_tolerance must be >= 0"),
    ],
)
def test_bad_values(kwargs, error, match):
    robot = get_robot("paddle4")
    fields = {"robot": robot, "waypoints": [robot.home, [0.5, 0.0, 0.1, 0.0]]}
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        Waypoints(**fields)


def test_still_waypoints_are_valid_and_refused_only_at_planning_time():
    robot = get_robot("paddle4")
    same = [[0.1, 0.0, 0.0, 0.0], [0.1 + 1e-13, 0.0, 0.0, 0.0]]
    problem = Waypoints(robot, same)  # a valid problem
    assert problem.still
    with pytest.raises(InvalidInputError, match="give segment_durations to hold still") as info:
        problem.require_motion("test")
    assert info.value.name == "waypoints"
    Waypoints(robot, same, segment_durations=[1.0]).require_motion("test")  # a hold
