"""Tests of robots.paddle_ik: the closed-form paddle4 IK of the ECE486 paddle task."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from hypothesis import example, given, settings
from hypothesis import strategies as st

from optraj.errors import InvalidInputError, JointLimitError, UnreachableError, WorkspaceError
from optraj.robots import PADDLE4_WORKSPACE, paddle4_ik, solve_ik
from optraj.robots.paddle_ik import BALL_OFFSET


@pytest.mark.parametrize(
    ("ball", "expected"),
    [
        ((1.1, 0.8, 0.7), [0.9000, 0.3911, 0.9985, -0.3911]),
        ((1.1, -0.8, 0.7), [0.9000, -0.3911, 0.9985, 0.3911]),
        ((1.1, -0.8, -0.1), [0.1000, -0.3911, 0.9985, 0.3911]),
        ((1.1, 0.8, -0.1), [0.1000, 0.3911, 0.9985, -0.3911]),
    ],
)
def test_seed_corner_solutions(ball, expected):
    np.testing.assert_allclose(paddle4_ik(get_robot("paddle4"), ball), expected, atol=1e-4)


def _ball_from_fk(robot, q):
    T = robot.tool_pose(q)
    return T[:3, 3] + BALL_OFFSET * T[:3, 2]


def test_fk_of_solution_meets_1000_random_balls():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(2024)
    low = [PADDLE4_WORKSPACE[a][0] for a in "xyz"]
    high = [PADDLE4_WORKSPACE[a][1] for a in "xyz"]
    for ball in rng.uniform(low, high, size=(1000, 3)):
        q = paddle4_ik(robot, ball)
        np.testing.assert_allclose(_ball_from_fk(robot, q), ball, atol=1e-12)
        # The paddle faces +x (C = 0) and stays in its plane: normal = world +x.
        np.testing.assert_allclose(robot.tool_pose(q)[:3, 2], [1, 0, 0], atol=1e-12)
        assert robot.limits.contains(q)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(
    x=st.floats(0.3, 1.1),
    y=st.floats(-0.8, 0.8),
    z=st.floats(-0.1, 0.7),
    angle=st.floats(-0.5, 0.5),
)
@example(x=1.09375, y=0.78125, z=0.0, angle=-0.5)  # found by hypothesis: J3 would be 1.0033 m
@example(x=1.1, y=-0.8, z=0.7, angle=0.5)
def test_contact_angle_turns_the_normal(x, y, z, angle):
    robot = get_robot("paddle4")
    try:
        q = paddle4_ik(robot, (x, y, z), contact_angle=angle)
    except JointLimitError:
        # Near the workspace's far corners a turned paddle needs J3 beyond 1 m. Cross-check
        # with the numerical IK: no configuration within the limits places the paddle there.
        turn = np.array(
            [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
        )
        target = robot.tool_pose(robot.home)
        target[:3, :3] = turn @ target[:3, :3]
        target[:3, 3] = np.array([x, y, z]) - BALL_OFFSET * target[:3, 2]
        with pytest.raises(UnreachableError):
            solve_ik(robot, target, restarts=10)
        return
    T = robot.tool_pose(q)
    np.testing.assert_allclose(_ball_from_fk(robot, q), (x, y, z), atol=1e-12)
    np.testing.assert_allclose(T[:3, 2], [np.cos(angle), np.sin(angle), 0.0], atol=1e-12)


@pytest.mark.parametrize(
    ("ball", "axis", "bound"),
    [
        ((1.2, 0.0, 0.3), "x", "x <= 1.1"),
        ((0.2, 0.0, 0.3), "x", "x >= 0.3"),
        ((0.8, -0.9, 0.3), "y", "y >= -0.8"),
        ((0.8, 0.0, 0.75), "z", "z <= 0.7"),
    ],
)
def test_ball_outside_workspace_names_the_bound(ball, axis, bound):
    with pytest.raises(WorkspaceError, match=bound) as info:
        paddle4_ik(get_robot("paddle4"), ball)
    assert info.value.axis == axis


def test_joint_limit_violation_names_joint_and_limit():
    # Paddle turned 100 deg from +x needs J4 beyond +pi/2.
    with pytest.raises(JointLimitError, match=r"'J4'.*upper limit 1\.5708") as info:
        paddle4_ik(get_robot("paddle4"), (0.8, 0.0, 0.3), contact_angle=np.radians(100))
    assert info.value.upper == pytest.approx(np.pi / 2)


def test_rejects_other_robots_and_bad_input():
    with pytest.raises(InvalidInputError, match="paddle4 robot only"):
        paddle4_ik(get_robot("sawyer"), (0.8, 0.0, 0.3))
    with pytest.raises(InvalidInputError, match="finite"):
        paddle4_ik(get_robot("paddle4"), (0.8, np.nan, 0.3))


def test_large_contact_angles_are_wrapped_or_rejected():
    robot = get_robot("paddle4")
    wrapped = paddle4_ik(robot, (0.8, 0.1, 0.3), contact_angle=0.2 - 2 * np.pi)
    np.testing.assert_allclose(wrapped, paddle4_ik(robot, (0.8, 0.1, 0.3), 0.2), atol=1e-12)
    with pytest.raises(InvalidInputError, match=r"contact_angle must lie in \[-2 pi, 2 pi\]"):
        paddle4_ik(robot, (0.8, 0.1, 0.3), contact_angle=1e20)
    with pytest.raises(InvalidInputError, match="paddle4 robot only"):
        paddle4_ik("paddle4", (0.8, 0.1, 0.3))
