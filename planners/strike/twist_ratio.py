r"""The twist ratio: the least share of its velocity limits an arm needs for a strike motion.

At contact the tool must move at ``speed`` along a direction: in a pool shot the cue tip moves
along the shot direction with its z axis (the cue axis) held on the line, free to turn about it
(roll); in a paddle shot the ball point moves along the paddle normal. At a configuration q the
joint velocities giving this motion form an affine set :math:`\{\dot q : A(q) \dot q = v\, b\}`,
and the smallest velocity-limit ratio over it is a small linear programme (LP),

.. math::

    r(q, v) = \min_{\dot q,\, s} s \quad \text{s.t.} \quad A \dot q = v\, b, \quad
    -s\, \dot q_{\max} \le \dot q \le s\, \dot q_{\max},

solved by :class:`planners.strike.min_max_ratio.MinMaxRatio`. A joint that moves nothing the
rows hold (the cue's roll about its own axis) stays still. The ratio is linear in the speed,
:math:`r(q, v) = v\, r_1(q)`, so the fastest strike the configuration allows within the
velocity limits is :math:`1 / r_1(q)`. :func:`twist_ratio` is the checked public entry;
:func:`unit_ratio` gives :math:`r_1` to the contact searches, which keep one LP for many
configurations.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.strike.min_max_ratio import MinMaxRatio
from optraj.problems.common import MAX_TOOL_SPEED, normal_pair, unit_vector
from optraj.robots import JointLimits, Robot
from optraj.validation import as_number, as_vector

__all__ = ["MAX_OFFSET", "binding_joints", "task_rows", "twist_ratio", "unit_ratio"]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

#: Longest lever :func:`twist_ratio` takes from the tool origin [m]: several times the length
#: of any arm here, so more is a unit mistake (and near 1e150 m the lever's products overflow).
MAX_OFFSET = 10.0


def task_rows(robot: Robot, q: FloatArray, offset: float, across: FloatArray | None) -> FloatArray:
    """Rows A with ``A qd`` = [point velocity; angular velocity along ``across``].

    Args:
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        offset: Distance of the point from the tool origin along the tool z axis [m].
        across: Unit vectors whose angular velocity rows are added, shape (2, 3); None for
            none.

    Returns:
        Shape (3, n), or (5, n) with the two ``across`` rows, in world axes.
    """
    jac = pin.computeFrameJacobian(robot.model, robot.data, q, robot.tool_frame_id, _WORLD_ALIGNED)
    rows = jac[:3]
    if offset != 0.0:
        lever = offset * robot.tool_pose(q)[:3, 2]
        rows = rows - pin.skew(lever) @ jac[3:]  # v + w x lever
    if across is not None:
        rows = np.vstack([rows, across @ jac[3:]])
    return rows


def unit_ratio(
    lp: MinMaxRatio,
    robot: Robot,
    q: FloatArray,
    direction: FloatArray,
    velocity_limit: FloatArray,
    offset: float,
    across: FloatArray | None,
) -> tuple[float, FloatArray]:
    """r_1(q) and an optimal joint velocity at unit speed, for callers that keep one LP.

    Args:
        lp: The LP solver, kept by the caller over its calls.
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        direction: Unit direction of the point's velocity, shape (3,).
        velocity_limit: Velocity limits [rad/s or m/s], shape (n,).
        offset: As :func:`task_rows`.
        across: As :func:`task_rows`: the angular velocity held still across the direction.

    Returns:
        ``(r1, qd1)``: the ratio at unit speed [s/m] and the joint velocity attaining it
        [rad/m or -], shape (n,); ``(inf, NaNs)`` when no joint velocity gives the motion.
    """
    rows = task_rows(robot, q, offset, across)
    target = np.zeros(rows.shape[0])
    target[:3] = direction
    y = lp(rows * velocity_limit, target)
    if y is None:
        return math.inf, np.full(q.size, np.nan)
    return float(np.abs(y).max()), y * velocity_limit


def binding_joints(qd: FloatArray, velocity_limit: FloatArray) -> list[int]:
    """Joints whose ratio is within 1e-9 (relative) of the largest, in joint order.

    Args:
        qd: Joint velocity [rad/s or m/s], shape (n,).
        velocity_limit: Velocity limits, shape (n,).

    Returns:
        The joint indices; empty when a velocity is not finite (the motion is impossible).
    """
    ratios = np.abs(qd) / velocity_limit
    if not np.all(np.isfinite(ratios)):
        return []
    top = float(ratios.max(initial=0.0))
    return [int(i) for i in np.flatnonzero(ratios >= top * (1.0 - 1e-9))]


def twist_ratio(
    robot: Robot,
    q: ArrayLike,
    direction: ArrayLike,
    speed: float,
    *,
    offset: float = 0.0,
    align_axis: bool = True,
    limits: JointLimits | None = None,
) -> tuple[float, FloatArray, int]:
    r"""Smallest velocity-limit ratio of a joint velocity giving a strike motion at q.

    The motion: the tool point (the tool origin moved ``offset`` along the tool z axis) moves
    at ``speed`` along the unit ``direction`` d; with ``align_axis`` the tool turns about d
    only (the angular velocity across d is zero, the roll rate about d free), which keeps a
    tool z axis lying along d on it. With :math:`e_1, e_2` completing d to an orthonormal
    basis and :math:`J_p = J_v - [\ell]_\times J_\omega` the point's rows (lever
    :math:`\ell` = offset times the tool z axis), it solves the LP

    .. math::

        \min_{\dot q} \max_i \frac{|\dot q_i|}{\dot q_{\max,i}} \quad \text{s.t.} \quad
        J_p \dot q = v\, d, \quad e_1^T J_\omega \dot q = e_2^T J_\omega \dot q = 0

    exactly: in NumPy, returning the least-norm optimal joint velocity, when A has a null space
    of one or two dimensions; else by HiGHS through CasADi. The ratio is linear in the speed.

    Args:
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        direction: Direction of the point's velocity, shape (3,) (normalised here).
        speed: Point speed [m/s], in [0, MAX_TOOL_SPEED].
        offset: Distance of the point from the tool origin along the tool z axis [m], at most
            :data:`MAX_OFFSET` either way.
        align_axis: Forbid turning across ``direction`` (pool cue); False leaves the angular
            velocity free (paddle).
        limits: Limits whose velocity limits [rad/s or m/s] are used; the robot's when None.

    Returns:
        ``(ratio, qd, joint)``: the smallest ``max_i |qd_i| / qd_max_i`` [-]; a joint velocity
        attaining it [rad/s or m/s], shape (n,); the index of the binding joint (the first of
        those whose ratio equals the largest). ``(0.0, zeros, 0)`` at speed 0, and
        ``(inf, NaNs, -1)`` at a singular configuration that cannot give the motion at all.

    Raises:
        InvalidInputError: Malformed robot, q, direction, speed, offset or limits. q need not
            lie within the position limits: the ratio is a property of the kinematics.
        SolverError: HiGHS fails (not expected: the LP is always feasible and bounded).
    """
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    config = as_vector(q, "q", robot.dof)
    unit = unit_vector(direction, "direction")
    speed_value = as_number(speed, "speed", "m/s", minimum=0.0, maximum=MAX_TOOL_SPEED)
    offset_value = as_number(offset, "offset", "m", minimum=-MAX_OFFSET, maximum=MAX_OFFSET)
    used = robot.limits if limits is None else limits
    if not isinstance(used, JointLimits) or used.names != robot.joint_names:
        raise InvalidInputError(
            f"limits must be a robots.JointLimits for the joints {robot.joint_names}",
            name="limits",
        )
    if speed_value == 0.0:
        return 0.0, np.zeros(robot.dof), 0
    velocity_limit = np.asarray(used.velocity, dtype=float)
    across = normal_pair(unit) if align_axis else None
    r1, qd1 = unit_ratio(MinMaxRatio(), robot, config, unit, velocity_limit, offset_value, across)
    qd = speed_value * qd1
    binding = binding_joints(qd, velocity_limit)
    return speed_value * r1, qd, binding[0] if binding else -1
