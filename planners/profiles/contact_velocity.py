"""Joint velocities that move a tool point at a given velocity, the tool not turning.

:func:`point_joint_velocity` solves the point and angular rows of the Jacobian in the least
squares sense; :func:`paddle_contact_velocity` applies it to a paddle strike (the ball point
at the strike speed along the paddle normal), the velocity at which a strike meets the ball.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.problems import PaddleStrike
from optraj.robots import Robot
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import as_vector

__all__ = ["paddle_contact_velocity", "point_joint_velocity"]

FloatArray = NDArray[np.float64]


def point_joint_velocity(
    robot: Robot, q: ArrayLike, velocity: ArrayLike, offset: float = 0.0
) -> FloatArray:
    """Joint velocity that moves a tool point at ``velocity`` without turning the tool.

    The point is the tool origin moved ``offset`` along the tool z axis; least squares on the
    stacked point and angular rows of the Jacobian (exact when the arm can do it).

    Args:
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        velocity: Point velocity [m/s], shape (3,).
        offset: Point offset along tool z [m].

    Returns:
        Joint velocity [rad/s or m/s], shape (n,).
    """
    config = as_vector(q, "q", robot.dof)
    target = as_vector(velocity, "velocity", 3)
    jac = robot.jacobian(config)
    lever = offset * robot.tool_pose(config)[:3, 2]
    # Velocity of the offset point: v + w x lever = v - [lever]x w.
    point_rows = jac[:3] - pin.skew(lever) @ jac[3:]
    task = np.vstack([point_rows, jac[3:]])
    return np.linalg.lstsq(task, np.concatenate([target, np.zeros(3)]), rcond=None)[0]


def paddle_contact_velocity(problem: PaddleStrike) -> FloatArray:
    """Joint velocity at contact of a paddle strike: ball point at speed along the normal."""
    return point_joint_velocity(
        problem.robot,
        problem.q_contact,
        float(problem.speed) * problem.normal,
        offset=BALL_OFFSET,
    )
