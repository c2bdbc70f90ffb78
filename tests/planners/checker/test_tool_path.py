"""Tests of planners.checker.tool_path: the tool on its line, its SLERP, and a speed cap."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from checker_support import Q0, T, quintic
from conftest import get_robot

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.trajectory import Trajectory
from optraj.problems import CartesianLine
from optraj.robots import Robot, solve_ik


def bump(trajectory: Trajectory, joint: int, height: float) -> Trajectory:
    """Add height * 16 s^2 (1 - s)^2 to one joint (zero value and slope at both ends)."""
    duration = trajectory.duration
    c = trajectory.coefficients.copy()
    c[0, 2:5, joint] += height * np.array([16, -32, 16]) / duration ** np.arange(2, 5)
    return Trajectory(trajectory.breakpoints, c)


def test_tool_path_on_and_off_the_line(paddle):
    q1 = Q0 + np.array([0.3, 0.0, 0.0, 0.0])  # J1 lifts the paddle straight up
    problem = CartesianLine(paddle, paddle.tool_pose(Q0), paddle.tool_pose(q1), q_start=Q0)
    straight = quintic(Q0, q1, T)
    report = check(straight, problem)
    assert report.ok, report.summary()
    assert report["tool path position"].value < 1e-12
    assert report["tool path orientation"].value < 1e-12

    sideways = check(bump(straight, 2, 1e-3), problem)  # J3 pushes the paddle along x
    off = sideways["tool path position"]
    assert [f.name for f in sideways.violations] == ["tool path position"]
    assert off.value == pytest.approx(1e-3, rel=1e-9)
    assert off.time == pytest.approx(T / 2, abs=1e-9)
    assert "off the line" in off.detail

    twisted = check(bump(straight, 3, 0.01), problem)  # J4 turns the paddle about z
    turn = twisted["tool path orientation"]
    assert not turn.ok
    assert turn.value == pytest.approx(0.01, rel=1e-9)
    assert turn.time == pytest.approx(T / 2, abs=1e-9)


def pose_path(robot: Robot, T0: np.ndarray, T1: np.ndarray, duration: float, lag: bool):
    """Joint motion along the line T0 -> T1, by IK and Hermite cubics.

    The tool moves along the line with a quintic time scaling s(t) (not at constant speed, so
    the fraction of the way differs from the fraction of the time); its orientation follows
    SLERP at s, or at s^2 with ``lag``.
    """
    times = np.linspace(0.0, duration, 41)
    turn = pin.log3(T0[:3, :3].T @ T1[:3, :3])
    qs, qds = [], []
    q = None
    for t in times:
        x = t / duration
        s = x**3 * (10 - 15 * x + 6 * x**2)
        ds = 30 * x**2 * (1 - x) ** 2 / duration
        r, dr = (s * s, 2 * s * ds) if lag else (s, ds)
        pose = np.eye(4)
        pose[:3, :3] = T0[:3, :3] @ pin.exp3(r * turn)
        pose[:3, 3] = T0[:3, 3] + s * (T1[:3, 3] - T0[:3, 3])
        q = solve_ik(robot, pose, q_near=robot.home if q is None else q).q
        twist = np.concatenate([(T1[:3, 3] - T0[:3, 3]) * ds, T0[:3, :3] @ turn * dr])
        qs.append(q)
        qds.append(np.linalg.lstsq(robot.jacobian(q), twist, rcond=None)[0])
    return Trajectory.from_hermite(times, qs, qds)


def test_tool_path_orientation_follows_slerp_by_position(sawyer):
    T0 = sawyer.tool_pose(sawyer.home)
    T1 = T0.copy()
    T1[:3, 3] += [0.1, 0.05, 0.0]
    T1[:3, :3] = pin.exp3(np.array([0.0, 0.0, np.radians(20.0)])) @ T0[:3, :3]
    problem = CartesianLine(sawyer, T0, T1, q_start=sawyer.home)
    report = check(pose_path(sawyer, T0, T1, 1.0, lag=False), problem)
    assert report.passed("tool path position", "tool path orientation"), report.summary()

    lagging = check(pose_path(sawyer, T0, T1, 1.0, lag=True), problem)
    turn = lagging["tool path orientation"]
    assert lagging["tool path position"].ok
    assert not turn.ok
    # The orientation lags the SLERP by (s - s^2) x 20 deg, most (5 deg) at s = 1/2.
    assert turn.value == pytest.approx(np.radians(5.0), rel=1e-2)
    assert turn.time == pytest.approx(0.5, abs=0.02)


def test_a_tool_speed_cap_is_verified_over_the_trajectory_and_a_tool_path():
    # The cap that Toppra(tool_speed=...) and CartesianLine(speed=) promise is verified.
    from optraj.planners import CartesianStraightLine, Toppra

    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.4)
    capped = check(Toppra(tool_speed=0.3).plan(move), move, tool_speed=0.3)["tool speed"]
    assert capped.ok and 0.29 < capped.value <= 0.3 + 1e-6 and capped.unit == "m/s"
    free = check(Toppra().plan(move), move, tool_speed=0.3)["tool speed"]
    assert not free.ok and free.value > 1.0
    start = robot.tool_pose(robot.home)
    goal = start.copy()
    goal[:3, 3] += [0.1, 0.0, 0.0]
    line = problems.CartesianLine(robot, start, goal, speed=0.05)
    report = check(CartesianStraightLine().plan(line), line)
    assert report["tool speed"].ok and report["tool speed"].value <= 0.05 + 1e-6
    fast = problems.CartesianLine(robot, start, goal, speed=0.01)
    assert not check(CartesianStraightLine().plan(line), fast)["tool speed"].ok
    with pytest.raises(InvalidInputError, match="tool_speed must be > 0 m/s"):
        check(Toppra().plan(move), move, tool_speed=-1.0)
