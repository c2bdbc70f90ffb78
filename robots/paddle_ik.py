r"""Closed-form inverse kinematics of the paddle4 robot (ECE486 paddle task).

The paddle meets the ball with its centre: the ball centre lies on the paddle normal, 0.06 m
from the joint-4 axis (joint radius 0.04 m + paddle thickness 0.01 m + ball radius 0.01 m).
For ball centre p = (px, py, pz) and contact angle C (paddle normal from +x, counter-clockwise
about +z):

.. math::

    \alpha = p_x + 0.9 - 0.06 \cos C, \quad \beta = p_y - 0.06 \sin C \\
    \theta_1 = p_z + 0.2, \quad \theta_2 = \operatorname{atan2}(\beta, \alpha), \quad
    \theta_3 = \sqrt{\alpha^2 + \beta^2} - 1.1, \quad \theta_4 = C - \theta_2

(the ECE486 text prints +0.06 sin C in beta; only the minus sign puts the paddle on the ball, and
both agree at C = 0, where every number of the ECE486 task lies). The solution is unique.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, WorkspaceError
from optraj.robots.robot import Robot
from optraj.validation import as_array, as_vector

__all__ = [
    "BALL_OFFSET",
    "PADDLE4_WORKSPACE",
    "paddle4_ik",
]

FloatArray = NDArray[np.float64]

#: Workspace cuboid of the ECE486 task: the ball centre must lie in it [m].
PADDLE4_WORKSPACE: dict[str, tuple[float, float]] = {
    "x": (0.3, 1.1),
    "y": (-0.8, 0.8),
    "z": (-0.1, 0.7),
}
#: Ball centre from the paddle centre along the paddle normal [m] (seed: the paddle centre is
#: 0.05 m and the ball centre 0.06 m from the joint-4 axis).
BALL_OFFSET = 0.01
#: Ball centre from the joint-4 axis along the paddle normal [m] (0.04 + 0.01 + 0.01).
_AXIS_TO_BALL = 0.06
#: Joint-2 axis position (x, y) [m] and joint-2-to-joint-4 distance at J3 = 0 [m].
_J2_AXIS_X = -0.9
_L2 = 1.1
#: Height of the paddle centre below joint 1's position [m].
_PADDLE_DROP = 0.2


def paddle4_ik(robot: Robot, ball: ArrayLike, contact_angle: float = 0.0) -> FloatArray:
    """Joint configuration that puts the paddle centre on the ball.

    Args:
        robot: The ``paddle4`` robot (its joint limits are checked).
        ball: Ball centre in the base frame [m], shape (3,).
        contact_angle: Angle C of the paddle normal from +x, counter-clockwise about +z [rad],
            in [-2 pi, 2 pi].

    Returns:
        q = [J1 [m], J2 [rad], J3 [m], J4 [rad]], shape (4,).

    Raises:
        WorkspaceError: The ball is outside the workspace cuboid; names the broken bound.
        JointLimitError: The solution needs a joint beyond its limits; names joint and limit.
        InvalidInputError: Not the paddle4 robot, or malformed input.
    """
    p = as_vector(ball, "ball", 3)
    if not isinstance(robot, Robot) or robot.name != "paddle4":
        raise InvalidInputError(
            f"paddle4_ik solves the paddle4 robot only, got {getattr(robot, 'name', robot)!r}",
            name="robot",
        )
    raw_angle = float(as_array(contact_angle, "contact_angle", ()))
    if abs(raw_angle) > 2 * math.pi:
        raise InvalidInputError(
            f"contact_angle must lie in [-2 pi, 2 pi] rad, got {raw_angle:.6g} rad",
            name="contact_angle",
        )
    # Wrapped to [-pi, pi], so that theta4 = C - theta2 keeps theta2's digits.
    angle = math.remainder(raw_angle, 2 * math.pi)
    for axis, value in zip("xyz", p, strict=True):
        lower, upper = PADDLE4_WORKSPACE[axis]
        if not lower <= value <= upper:
            raise WorkspaceError(p.tolist(), axis, value, lower, upper)
    alpha = p[0] - _J2_AXIS_X - _AXIS_TO_BALL * np.cos(angle)
    beta = p[1] - _AXIS_TO_BALL * np.sin(angle)
    theta2 = np.arctan2(beta, alpha)
    q = np.array(
        [
            p[2] + _PADDLE_DROP,
            theta2,
            np.hypot(alpha, beta) - _L2,
            np.arctan2(np.sin(angle - theta2), np.cos(angle - theta2)),  # same angle, in (-pi, pi]
        ]
    )
    robot.limits.check_position(q, tolerance=1e-12, context=f"paddle4 IK for ball {p.tolist()}")
    return q
