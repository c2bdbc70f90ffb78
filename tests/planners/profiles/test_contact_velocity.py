"""Tests of planners.profiles.contact_velocity: joint velocities that move a tool point."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.planners.profiles.contact_velocity import (
    paddle_contact_velocity,
    point_joint_velocity,
)
from optraj.robots.paddle_ik import BALL_OFFSET


def _point(robot, q, offset):
    """The tool point ``offset`` along the tool z axis, in world coordinates [m]."""
    pose = robot.tool_pose(q)
    return pose[:3, 3] + offset * pose[:3, 2]


def _rotation(robot, q):
    return robot.tool_pose(q)[:3, :3]


@pytest.mark.parametrize("offset", [0.0, 0.3])
def test_the_point_moves_at_the_velocity_and_the_tool_does_not_turn(offset):
    # Checked against finite differences of the forward kinematics along q + h qd.
    robot = get_robot("sawyer")
    rng = np.random.default_rng(5)
    q = robot.limits.sample(rng, 1)[0] * 0.5 + 0.5 * robot.home
    velocity = np.array([0.2, -0.1, 0.05])
    qd = point_joint_velocity(robot, q, velocity, offset=offset)
    h = 1e-6
    moved = (_point(robot, q + h * qd, offset) - _point(robot, q - h * qd, offset)) / (2 * h)
    np.testing.assert_allclose(moved, velocity, rtol=0, atol=1e-7)
    turned = _rotation(robot, q + h * qd) - _rotation(robot, q - h * qd)
    np.testing.assert_allclose(turned / (2 * h), 0.0, atol=1e-7)


def test_the_paddle_meets_the_ball_at_speed_along_the_normal():
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=(1.0, 0.3, 0.4), contact_angle=0.3, speed=0.5)
    qd = paddle_contact_velocity(problem)
    np.testing.assert_allclose(
        qd, point_joint_velocity(robot, problem.q_contact, 0.5 * problem.normal, BALL_OFFSET)
    )
    q, h = problem.q_contact, 1e-6
    moved = (_point(robot, q + h * qd, BALL_OFFSET) - _point(robot, q - h * qd, BALL_OFFSET)) / (
        2 * h
    )
    np.testing.assert_allclose(moved, 0.5 * problem.normal, rtol=0, atol=1e-6)
