"""Tests of planners.time_optimal.toppra_path_checks: paths within the limits, no corners."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InvalidInputError, JointLimitError
from optraj.planners.checker import check
from optraj.planners.time_optimal.toppra_path import GeometricPath
from optraj.planners.time_optimal.toppra_path_checks import (
    check_path_positions,
    check_tangent,
    waypoint_path,
)
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.trajectory import Trajectory

KINEMATIC = ("position", "velocity", "acceleration")


def test_waypoint_outside_the_joint_limits_is_a_typed_error():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    bad = q0.copy()
    bad[1] = limits.upper[1] + 0.1
    with pytest.raises(JointLimitError) as info:
        Toppra().time_parametrize(np.array([q0, bad]), limits)
    assert info.value.joint == robot.joint_names[1]
    with pytest.raises(JointLimitError):
        problems.Waypoints(robot, [q0, bad])


def test_trajectory_path_through_a_joint_limit_names_the_joint():
    robot = get_robot("paddle4")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[2] = limits.upper[2] - 0.01
    # a cubic that overshoots past q1 (and the limit) before coming back to it
    path = Trajectory.from_hermite([0.0, 1.0], [q0, q1], [2.0 * (q1 - q0), -(q1 - q0)])
    with pytest.raises(JointLimitError) as info:
        Toppra().time_parametrize(path, limits)
    assert info.value.joint == robot.joint_names[2]
    assert "s = " in str(info.value)


def test_spline_leaving_the_limits_falls_back_to_a_shape_preserving_path():
    robot = get_robot("paddle4")
    limits = robot.limits
    rng = np.random.default_rng(5)
    for _ in range(50):
        points = robot.random_configurations(5, rng)
        traj = Toppra(gridpoints=60).time_parametrize(points, limits)
        assert check(traj, robot, quantities=KINEMATIC).ok
        if traj.metadata["path"].startswith("pchip"):
            with pytest.raises(JointLimitError):  # the spline would have left the limits
                Toppra().time_parametrize(Trajectory(*_spline_as_trajectory(points)), limits)
            break
    else:
        pytest.fail("no random case needed the fallback")


def _spline_as_trajectory(points):
    spline = GeometricPath.spline(points)
    return spline.knots, spline.coefficients


def test_a_corner_is_refused_and_a_smooth_path_passes():
    limits = get_robot("paddle4").limits
    q0 = np.array([0.1, 0.2, 0.3, 0.0])
    smooth = GeometricPath.spline(np.array([q0, q0 + 0.1, q0 + np.array([0.3, 0.1, 0.2, 0.0])]))
    check_tangent(smooth, limits)
    corner = GeometricPath.from_trajectory(
        Trajectory(
            [0.0, 1.0, 2.0],
            np.array([[q0, np.full(4, 0.1)], [q0 + 0.1, np.array([0.1, -0.1, 0.1, 0.1])]]),
        )
    )
    with pytest.raises(InvalidInputError, match="corner"):
        check_tangent(corner, limits)


def test_waypoint_path_merges_repeated_waypoints_and_maps_them_to_knots():
    limits = get_robot("paddle4").limits
    q0 = np.array([0.1, 0.2, 0.3, 0.0])
    q1 = q0 + 0.2
    path, index = waypoint_path(np.array([q0, q0, q1, q1 + 1e-13]), limits)
    np.testing.assert_array_equal(index, [0, 0, 1, 1])
    assert path.kind == "straight line" or path.knots.size == 2
    check_path_positions(path, limits)  # within: no error
    with pytest.raises(InvalidInputError, match="same configuration"):
        waypoint_path(np.array([q0, q0]), limits)
