"""The shortest time any planner could need for a joint move under box limits.

With independent box limits on each joint's velocity, acceleration and jerk, no joint can
finish faster than it could alone, so the largest of the single-joint minimum times is a
lower bound for every planner (cubic, LSPB, TOPPRA, optimal control...): benchmarks quote
durations relative to it. A single joint's minimum time under velocity, acceleration and jerk
limits is what Ruckig computes exactly (step 1 of its algorithm, one joint at a time), so
:func:`lower_bound` asks Ruckig for every joint's ``independent_min_durations`` in one call;
the time-synchronised Ruckig move attains the bound.

:func:`lower_bound_va` is the closed form without a jerk limit (a trapezoidal velocity
profile, or a triangle when the cruise speed is never reached), an independent cross-check:
as the jerk limit grows, :func:`lower_bound` tends to it from above.

Accelerations at the ends are taken as given, zero when not prescribed; position limits are
ignored (dropping a constraint can only lower the bound, so it remains a bound).

:func:`check_state_torques` is the same kind of necessary condition for the effort limits:
the torques of a joint state a problem prescribes (a start at rest, a goal state) are its
inverse dynamics whatever the motion through it, so a state that needs more than a joint's
effort limit (to hold the arm against gravity, say) refuses the whole motion before any solve.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.checker import round_off
from optraj.planners.time_optimal.ruckig_calculation import calculate, ruckig_input
from optraj.planners.time_optimal.ruckig_validation import (
    check_boundary_states,
    checked_limits,
    state_or_zeros,
)
from optraj.problems import PointToPoint
from optraj.robots import JointLimits, Robot
from optraj.validation import as_array, as_vector, ndim_of

__all__ = ["check_state_torques", "joint_min_durations", "lower_bound", "lower_bound_va"]

FloatArray = NDArray[np.float64]


class _Move(NamedTuple):
    """The keyword form of a move as given: every field None when the problem form is used."""

    q_start: ArrayLike | None
    q_goal: ArrayLike | None
    qd_start: ArrayLike | None
    qd_goal: ArrayLike | None
    qdd_start: ArrayLike | None
    qdd_goal: ArrayLike | None
    limits: JointLimits | None


def joint_min_durations(
    problem: PointToPoint | None = None,
    *,
    q_start: ArrayLike | None = None,
    q_goal: ArrayLike | None = None,
    qd_start: ArrayLike | None = None,
    qd_goal: ArrayLike | None = None,
    qdd_start: ArrayLike | None = None,
    qdd_goal: ArrayLike | None = None,
    limits: JointLimits | None = None,
) -> FloatArray:
    """Each joint's own minimum time for the move under its velocity/acceleration/jerk limits.

    Give either a :class:`problems.PointToPoint` (its states and limits are used) or the
    keyword form (``q_start``, ``q_goal`` and ``limits`` required; velocities and
    accelerations default to zero)::

        joint_min_durations(problem)
        joint_min_durations(q_start=q0, q_goal=q1, limits=robot.limits)

    Args:
        problem: The move, or None for the keyword form.
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
        qd_start: Start velocities [rad/s or m/s], shape (n,); rest when None.
        qd_goal: Goal velocities [rad/s or m/s], shape (n,); rest when None.
        qdd_start: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        qdd_goal: Goal accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Joint limits (velocity, acceleration, jerk).

    Returns:
        Minimum durations [s], shape (n,); 0 for a joint already in its goal state.

    Raises:
        InvalidInputError: Both or neither of the two forms, missing arguments, bad shapes.
        InfeasibleError: A start or goal state no motion within the limits can leave or
            reach (names the joint).
        SolverError: Ruckig fails; carries its status.
    """
    given = _Move(q_start, q_goal, qd_start, qd_goal, qdd_start, qdd_goal, limits)
    return _min_durations(problem, given)


def lower_bound(
    problem: PointToPoint | None = None,
    *,
    q_start: ArrayLike | None = None,
    q_goal: ArrayLike | None = None,
    qd_start: ArrayLike | None = None,
    qd_goal: ArrayLike | None = None,
    qdd_start: ArrayLike | None = None,
    qdd_goal: ArrayLike | None = None,
    limits: JointLimits | None = None,
) -> float:
    """The time [s] no trajectory within the joints' box limits can beat for this move.

    The largest of :func:`joint_min_durations`: each joint's exact minimum time under its
    velocity, acceleration and jerk limits (single-axis Ruckig).

    Args:
        problem: A :class:`problems.PointToPoint`, or None for the keyword form.
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
        qd_start: Start velocities [rad/s or m/s], shape (n,); rest when None.
        qd_goal: Goal velocities [rad/s or m/s], shape (n,); rest when None.
        qdd_start: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        qdd_goal: Goal accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Joint limits (velocity, acceleration, jerk).

    Returns:
        The bound [s], >= 0 (0 when every joint is already in its goal state).

    Raises:
        See :func:`joint_min_durations`.
    """
    given = _Move(q_start, q_goal, qd_start, qd_goal, qdd_start, qdd_goal, limits)
    return float(np.max(_min_durations(problem, given)))


def _min_durations(problem: PointToPoint | None, given: _Move) -> FloatArray:
    """The body of :func:`joint_min_durations` (and so of :func:`lower_bound`)."""
    move = _keyword_form(problem, given)
    if move.q_start is None or move.q_goal is None or move.limits is None:
        missing = [name for name in ("q_start", "q_goal", "limits") if getattr(move, name) is None]
        raise InvalidInputError(
            f"the lower bound needs a PointToPoint or q_start, q_goal and limits; missing "
            f"{', '.join(missing)}",
            name=missing[0],
        )
    box = checked_limits(move.limits)
    n = box.n
    q0 = as_vector(move.q_start, "q_start", n)
    q1 = as_vector(move.q_goal, "q_goal", n)
    v0 = state_or_zeros(move.qd_start, "qd_start", n)
    v1 = state_or_zeros(move.qd_goal, "qd_goal", n)
    a0 = state_or_zeros(move.qdd_start, "qdd_start", n)
    a1 = state_or_zeros(move.qdd_goal, "qdd_goal", n)
    check_boundary_states(box, (v0, a0), (v1, a1))
    inp = ruckig_input(
        box,
        q0,
        q1,
        (v0.tolist(), a0.tolist(), v1.tolist(), a1.tolist()),
        synchronization=ruckig.Synchronization.No,
        minimum_duration=None,
    )
    native = calculate(inp, box)
    return np.asarray(native.independent_min_durations, dtype=float)


def _keyword_form(problem: PointToPoint | None, given: _Move) -> _Move:
    """The move from the problem, or the keywords given when there is no problem.

    Raises:
        InvalidInputError: A problem that is no PointToPoint, or both forms at once.
    """
    if problem is None:
        return given
    if not isinstance(problem, PointToPoint):
        raise InvalidInputError(
            f"the lower bound is for a problems.PointToPoint, got {type(problem).__name__}",
            name="problem",
        )
    named = [name for name, value in given._asdict().items() if value is not None]
    if named:
        raise InvalidInputError(
            f"give a problem or keyword arguments, not both (got {', '.join(named)})",
            name=named[0],
        )
    return _Move(*(getattr(problem, name) for name in _Move._fields))


def check_state_torques(
    robot: Robot,
    limits: JointLimits,
    states: Sequence[tuple[str, ArrayLike, ArrayLike, ArrayLike]],
) -> None:
    """Raise when a prescribed joint state needs more torque than the effort limits allow.

    Args:
        robot: The robot (its inverse dynamics, gravity included).
        limits: The limits planned for (their ``effort`` [N m or N]).
        states: ``(what, q, qd, qdd)`` of each state the problem fixes, e.g.
            ``("the start state (at rest)", q, 0, 0)``: positions [rad or m], velocities
            [rad/s or m/s] and accelerations [rad/s^2 or m/s^2], each shape (n,).

    Raises:
        InfeasibleError: ``limit="effort"``, the joint whose torque exceeds its limit the
            most (by more than the checker's slack), ``required`` and ``allowed`` [N m or
            N]; the message names the state, the ratio and the factor on the effort limits
            a plan needs at least.
        InvalidInputError: A state of the wrong shape or not finite.
    """
    if not isinstance(robot, Robot) or not isinstance(limits, JointLimits):
        raise InvalidInputError(
            "check_state_torques takes a robots.Robot and robots.JointLimits", name="robot"
        )
    n = limits.n
    worst: tuple[float, str, int, float] | None = None
    for what, q, qd, qdd in states:
        tau = robot.inverse_dynamics(
            as_vector(q, "q", n), as_vector(qd, "qd", n), as_vector(qdd, "qdd", n)
        )
        excess = np.abs(tau) - limits.effort - round_off(limits.effort)
        ratio = np.abs(tau) / limits.effort
        joint = int(np.argmax(ratio))
        if excess[joint] > 0.0 and (worst is None or ratio[joint] > worst[0]):
            worst = (float(ratio[joint]), str(what), joint, float(tau[joint]))
    if worst is None:
        return
    share, what, joint, torque = worst
    name, allowed = limits.names[joint], float(limits.effort[joint])
    unit = limits.unit("effort", joint)
    raise InfeasibleError(
        f"{what} needs joint {name!r} at {abs(torque):.4g} {unit}, {100.0 * share:.1f} % of its "
        f"effort limit {allowed:.4g} {unit}, whatever the motion through it (a prescribed "
        f"state's torques are its inverse dynamics): a plan needs effort limits at least "
        f"{share:.4g} times as large, or another state",
        limit="effort",
        joint=name,
        required=abs(torque),
        allowed=allowed,
    )


def lower_bound_va(delta: ArrayLike, vmax: ArrayLike, amax: ArrayLike) -> float:
    """Closed-form rest-to-rest minimum time with velocity and acceleration limits only.

    Per joint, a displacement ``d`` with ``|d| >= vmax^2 / amax`` takes the trapezoid's
    ``|d| / vmax + vmax / amax``; a shorter one never reaches ``vmax`` and takes the
    triangle's ``2 sqrt(|d| / amax)``. The bound is the largest over the joints. Without a
    jerk limit this is a lower bound for any jerk limit too.

    Args:
        delta: Displacements [rad or m], shape (n,) or scalar.
        vmax: Velocity limits [rad/s or m/s], > 0, broadcastable to delta.
        amax: Acceleration limits [rad/s^2 or m/s^2], > 0, broadcastable to delta.

    Returns:
        The bound [s], >= 0.

    Raises:
        InvalidInputError: Non-finite values, limits <= 0, or shapes that do not broadcast.
    """
    arrays = []
    for name, value in (("delta", delta), ("vmax", vmax), ("amax", amax)):
        scalar = ndim_of(value) == 0  # ragged is -1: as_vector names the shape
        array = np.atleast_1d(as_array(value, name, ()) if scalar else as_vector(value, name))
        if name != "delta" and np.any(array <= 0.0):
            raise InvalidInputError(f"{name} must be > 0, got {value!r}", name=name)
        arrays.append(array)
    try:
        d, v, a = np.broadcast_arrays(*arrays)
    except ValueError as exc:
        shapes = ", ".join(str(array.shape) for array in arrays)
        raise InvalidInputError(
            f"delta, vmax and amax must broadcast to one shape, got {shapes}", name="delta"
        ) from exc
    distance = np.abs(d)
    trapezoid = distance / v + v / a
    triangle = 2.0 * np.sqrt(distance / a)
    times = np.where(distance >= v * v / a, trapezoid, triangle)
    return float(np.max(times)) if times.size else 0.0
