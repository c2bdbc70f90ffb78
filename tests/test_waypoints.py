"""Tests of problems.waypoints."""

from __future__ import annotations

import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, JointLimitError
from problems import BoundaryState, ViaPoint, Waypoints


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
        ({"segment_durations": [0.0]}, InvalidInputError, "must be > 0 s"),
        ({"segment_durations": [1.0, 1.0]}, InvalidInputError, r"shape \(1,\)"),
        ({"via_tolerance": -1.0}, InvalidInputError, "via_tolerance must be >= 0"),
    ],
)
def test_bad_values(kwargs, error, match):
    robot = get_robot("paddle4")
    fields = {"robot": robot, "waypoints": [robot.home, [0.5, 0.0, 0.1, 0.0]]}
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        Waypoints(**fields)
