"""Tests of problems.cartesian_line."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, UnreachableError
from optraj.problems import BoundaryState, CartesianLine, ToolPath


def test_start_configuration_found_by_ik_and_constraints():
    robot = get_robot("sawyer")
    start = robot.tool_pose(robot.home)
    goal = start.copy()
    goal[:3, 3] += [0.1, 0.0, 0.0]
    problem = CartesianLine(robot, start, goal)
    np.testing.assert_allclose(robot.tool_pose(problem.q_start), start, atol=1e-8)
    assert problem.length == pytest.approx(0.1)
    kinds = [type(c) for c in problem.constraints()]
    assert kinds == [BoundaryState, ToolPath, BoundaryState]


def test_unreachable_goal_and_inconsistent_start_are_errors():
    robot = get_robot("sawyer")
    start = robot.tool_pose(robot.home)
    far = start.copy()
    far[:3, 3] += [3.0, 0.0, 0.0]
    with pytest.raises(UnreachableError):
        CartesianLine(robot, start, far)
    with pytest.raises(InvalidInputError, match="q_start puts the tool"):
        CartesianLine(robot, start, start, q_start=np.zeros(7))
    with pytest.raises(InvalidInputError, match="rotation matrix"):
        CartesianLine(robot, np.diag([1.0, 1.0, -1.0, 1.0]), start)
    with pytest.raises(InvalidInputError, match="speed must be > 0"):
        CartesianLine(robot, start, start, q_start=robot.home, speed=0.0)
    # Extreme values are refused with their bound and unit.
    with pytest.raises(InvalidInputError, match="speed must be <= 343 m/s"):
        CartesianLine(robot, start, start, q_start=robot.home, speed=1e308)
    with pytest.raises(InvalidInputError, match="duration must be >= 1e-06 s"):
        CartesianLine(robot, start, start, q_start=robot.home, duration=1e-200)
    with pytest.raises(InvalidInputError, match="duration must be <= 86400 s"):
        CartesianLine(robot, start, start, q_start=robot.home, duration=1e200)


def test_a_still_line_is_valid_and_refused_only_at_planning_time():
    # The rule of PointToPoint, for a tool line.
    robot = get_robot("sawyer")
    start = robot.tool_pose(robot.home)
    line = CartesianLine(robot, start, start.copy(), q_start=robot.home)
    assert line.still
    with pytest.raises(InvalidInputError, match="T_goal equals T_start") as info:
        line.require_motion("test")
    assert info.value.name == "T_goal" and "give a duration to hold still" in str(info.value)
    CartesianLine(robot, start, start, q_start=robot.home, duration=0.5).require_motion("test")
    moved = start.copy()
    moved[:3, 3] += [2e-12, 0.0, 0.0]
    assert not CartesianLine(robot, start, moved, q_start=robot.home).still
