"""Time-optimal jerk-limited moves between joint states with Ruckig, checked against limits.

:func:`state_to_state` is the fastest move from one joint state (position, velocity,
acceleration) to another under box velocity, acceleration and jerk limits; :func:`stop` the
fastest stop from a moving state, its position free (Ruckig's velocity interface)::

    traj = state_to_state(q0, qd0, None, q1, qd1, None, limits)   # a degree-3 Trajectory
    brake = stop(q1, qd1, None, limits)

Limits are checked three times. The start and target states are validated before Ruckig
runs (a target that no motion within the limits can reach raises :class:`InfeasibleError`
naming the joint). The position limits, which Ruckig's open-source version does not plan
around, are checked when a move is planned (:mod:`~planners.time_optimal.ruckig_limits`). And
the exact peaks of the finished polynomials are compared with every limit. Ruckig plans much
faster than the polynomials are built, so a checked move's polynomials are built on first use
(:meth:`Trajectory.deferred`); its duration, phases and metadata are there at once. Its
polynomials are never handed out unchecked: a breach found when they are built (which would be
a fault of Ruckig's) raises :class:`SolverError`.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.time_optimal.ruckig_calculation import calculate, reused_input
from optraj.planners.time_optimal.ruckig_conversion import native_pieces
from optraj.planners.time_optimal.ruckig_limits import (
    checked_pieces,
    ends_breach,
    limit_violations,
    position_breach,
)
from optraj.planners.time_optimal.ruckig_validation import (
    check_boundary_states,
    check_unsynchronised,
    checked_limits,
    longest_minimum_duration,
    result_joint_names,
    state_or_zeros,
    synchronization_option,
)
from optraj.planners.trajectory import Phase, Trajectory
from optraj.robots import JointLimits
from optraj.validation import as_flag, as_vector

__all__ = ["move_between_states", "state_to_state", "stop"]

FloatArray = NDArray[np.float64]

#: Ruckig's control interfaces by name: move to a target state, or only to a velocity.
_INTERFACES = {
    "position": ruckig.ControlInterface.Position,
    "velocity": ruckig.ControlInterface.Velocity,
}


def move_between_states(
    limits: JointLimits,
    start: FloatArray,
    v0: FloatArray,
    a0: FloatArray | None,
    goal: FloatArray,
    v1: FloatArray,
    a1: FloatArray | None,
    *,
    started: float,
    synchronization: str,
    minimum_duration: float | None,
    check_limits: bool,
    joint_names: Sequence[str] | None,
    interface: str = "position",
) -> Trajectory:
    """Plan one move from validated states (positions within their limits).

    The common part of :func:`state_to_state`, :func:`stop` and :meth:`Ruckig.plan`, which
    validate their arguments first. With ``check_limits`` the start state must be within the
    limits; the result is then exact and checked, but its polynomials are built on first use
    (:meth:`Trajectory.deferred`), since Ruckig plans faster than the conversion runs.
    Without it, the polynomials are built and every breach is listed at once.

    Args:
        limits: Joint limits.
        start: Start positions [rad or m], shape (n,).
        v0: Start velocities [rad/s or m/s], shape (n,).
        a0: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        goal: Target positions [rad or m], shape (n,) (the start again for a stop).
        v1: Target velocities [rad/s or m/s], shape (n,).
        a1: Target accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        started: ``time.perf_counter()`` when planning began, for ``solve_time``.
        synchronization: One of :data:`SYNCHRONIZATIONS`.
        minimum_duration: Shortest duration [s], or None.
        check_limits: Raise on a breach (see :func:`state_to_state`), else list them.
        joint_names: Names in the result; those of ``limits`` when None.
        interface: ``"position"`` (a move to the target state) or ``"velocity"`` (a stop).

    Returns:
        See :func:`state_to_state` and :func:`stop`.

    Raises:
        See :func:`state_to_state` and :func:`stop`.
    """
    n = limits.n
    # Lists: testing seven floats in Python is cheaper than one NumPy call.
    rest = [0.0] * n
    states = (
        v0.tolist(),
        rest if a0 is None else a0.tolist(),
        v1.tolist(),
        rest if a1 is None else a1.tolist(),
    )
    moving = any(states[0]) or any(states[1]) or any(states[2]) or any(states[3])
    if moving:
        zeros = np.zeros(n)
        a0 = zeros if a0 is None else a0
        a1 = zeros if a1 is None else a1
        check_unsynchronised(synchronization, v1, a1)
        check_boundary_states(limits, (v0, a0) if check_limits else None, (v1, a1))
    inp = reused_input(
        limits,
        start,
        goal,
        states if moving else None,
        synchronization=synchronization_option(synchronization),
        minimum_duration=minimum_duration,
        interface=_INTERFACES[interface],
    )
    native = calculate(inp, limits)
    duration = float(native.duration)
    if duration <= 0.0:
        raise _nothing_to_do(interface)
    stopping = interface == "velocity"
    pieces: tuple[FloatArray, FloatArray] | None = None
    if check_limits:
        # From rest to rest a joint stays between its start and its target, so only those
        # two are checked (see ends_breach); other moves are checked exactly. Every move's
        # polynomials are checked again when first built.
        breach = (
            position_breach(native, limits, start, None if stopping else goal)
            if moving
            else ends_breach(native, limits, start, goal)
        )
        if breach is not None:
            raise breach
        errors: list[InfeasibleError] = []
    else:
        pieces = native_pieces(native)
        errors = limit_violations(*pieces, limits)
    metadata = _metadata(native, errors, synchronization, minimum_duration, interface)
    names = result_joint_names(joint_names, limits)
    phases = (Phase("stop" if stopping else "move", 0.0, duration),)
    if pieces is None:
        traj = Trajectory.deferred(
            duration,
            n,
            functools.partial(checked_pieces, native, limits),
            joint_names=names,
            phases=phases,
            metadata=metadata,
        )
    else:
        traj = Trajectory(*pieces, joint_names=names, phases=phases, metadata=metadata)
    traj.metadata["solve_time"] = time.perf_counter() - started
    return traj


def _nothing_to_do(interface: str) -> InvalidInputError:
    """The error for a move of zero duration: nothing to stop, or nowhere to go."""
    if interface == "velocity":
        return InvalidInputError("nothing to stop: the joints are already at rest", name="qd0")
    return InvalidInputError(
        "q_goal equals q_start and the boundary velocities and accelerations match, so "
        "the move lasts 0 s: give a minimum_duration to hold still",
        name="q_goal",
    )


def _metadata(
    native: ruckig.Trajectory,
    errors: list[InfeasibleError],
    synchronization: str,
    minimum_duration: float | None,
    interface: str,
) -> dict[str, Any]:
    """A move's metadata but ``solve_time``: what :func:`planners.base.stamp` writes and more.

    Assembled in one go rather than through ``stamp``: this path costs little more than
    Ruckig itself.
    """
    metadata = {
        "planner": "ruckig",
        "status": "limits exceeded" if errors else "ok",
        "limit_violations": [str(error) for error in errors],
        "independent_min_durations": np.array(native.independent_min_durations, dtype=float),
        "native": native,
        "synchronization": synchronization,
    }
    if interface == "velocity":
        metadata["interface"] = interface
    else:
        metadata["minimum_duration"] = minimum_duration
    return metadata


def state_to_state(
    q0: ArrayLike,
    qd0: ArrayLike | None,
    qdd0: ArrayLike | None,
    q1: ArrayLike,
    qd1: ArrayLike | None,
    qdd1: ArrayLike | None,
    limits: JointLimits,
    *,
    synchronization: str = "time",
    minimum_duration: float | None = None,
    joint_names: Sequence[str] | None = None,
    check_limits: bool = True,
) -> Trajectory:
    """The time-optimal jerk-limited move from one joint state to another.

    Args:
        q0: Start positions [rad or m], shape (n,).
        qd0: Start velocities [rad/s or m/s], shape (n,); rest when None.
        qdd0: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        q1: Target positions [rad or m], shape (n,).
        qd1: Target velocities [rad/s or m/s], shape (n,); rest when None.
        qdd1: Target accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Velocity, acceleration and jerk limits (and position limits, checked).
        synchronization: One of :data:`SYNCHRONIZATIONS`.
        minimum_duration: Shortest duration [s]; a longer move is stretched to it.
        joint_names: Names in the result; those of ``limits`` when None.
        check_limits: Raise when the move breaks a limit (the default). With False it is
            returned with the breaches listed in ``metadata["limit_violations"]`` and
            ``metadata["status"] == "limits exceeded"``; only a start state out of the
            limits can cause one (Ruckig brakes it back first), or an overshoot of a
            position limit.

    Returns:
        A degree-3 trajectory with one phase ``move``; metadata holds ``planner``
        (``"ruckig"``), ``solve_time`` [s], ``status``, ``independent_min_durations`` [s]
        (shape (n,), each joint's own fastest time), ``synchronization``,
        ``minimum_duration``, ``limit_violations`` and ``native`` (the ``ruckig.Trajectory``).
        With ``check_limits`` its polynomials are built on first use (the duration,
        phases and metadata are there at once; see :meth:`Trajectory.deferred`).

    Raises:
        InfeasibleError: A start or target state out of the limits or out of reach within
            them (names the joint, the required and the allowed value), or a move that
            breaks a limit on the way (e.g. overshoots a position limit).
        JointLimitError: A start or target position outside the position limits.
        InvalidInputError: Bad shapes or values, nothing to move and no minimum duration,
            a minimum duration outside [1e-6, 86400] s, joint names that are not n strings,
            a check_limits that is not a bool, or synchronisation ``none`` with a target
            that is not at rest.
        UnknownNameError: An unknown synchronisation.
        SolverError: Ruckig fails otherwise; carries its status. Also raised by the first
            use of the polynomials if they break a limit (a fault of Ruckig's).
    """
    started = time.perf_counter()
    limits = checked_limits(limits)
    synchronization_option(synchronization)
    minimum = longest_minimum_duration(minimum_duration)
    check_limits = as_flag(check_limits, "check_limits")
    n = limits.n
    start = as_vector(q0, "q0", n)
    goal = as_vector(q1, "q1", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    limits.check_position(goal, tolerance=1e-9, context="target position")
    return move_between_states(
        limits,
        start,
        state_or_zeros(qd0, "qd0", n),
        state_or_zeros(qdd0, "qdd0", n),
        goal,
        state_or_zeros(qd1, "qd1", n),
        state_or_zeros(qdd1, "qdd1", n),
        started=started,
        synchronization=synchronization,
        minimum_duration=minimum,
        check_limits=check_limits,
        joint_names=joint_names,
    )


def stop(
    q0: ArrayLike,
    qd0: ArrayLike,
    qdd0: ArrayLike | None,
    limits: JointLimits,
    *,
    synchronization: str = "time",
    joint_names: Sequence[str] | None = None,
    check_limits: bool = True,
) -> Trajectory:
    """The fastest stop from a moving state within the limits; the position is free.

    Ruckig's velocity interface brings every joint to zero velocity and acceleration as
    fast as the acceleration and jerk limits allow (with ``synchronization="time"`` all
    joints come to rest together, at the slowest joint's time).

    Args:
        q0: Start positions [rad or m], shape (n,).
        qd0: Start velocities [rad/s or m/s], shape (n,).
        qdd0: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Joint limits; the result is checked against all of them.
        synchronization: One of :data:`SYNCHRONIZATIONS`.
        joint_names: Names in the result; those of ``limits`` when None.
        check_limits: Raise when the stop breaks a limit (default), else list the breaches
            in ``metadata["limit_violations"]`` (e.g. a stop that runs past a position
            limit: it is still the shortest possible stop).

    Returns:
        A degree-3 trajectory with one phase ``stop``, ending at rest; metadata as for
        :func:`state_to_state` plus ``stop_position`` [rad or m], shape (n,).

    Raises:
        InfeasibleError: The start state is out of the limits, or the stop breaks a limit
            (names the joint and the values).
        JointLimitError: A start position outside the position limits.
        InvalidInputError: Bad shapes or values, joint names that are not n strings, a
            check_limits that is not a bool, or the state is already at rest.
        SolverError: Ruckig fails; carries its status.
    """
    started = time.perf_counter()
    limits = checked_limits(limits)
    synchronization_option(synchronization)
    check_limits = as_flag(check_limits, "check_limits")
    n = limits.n
    start = as_vector(q0, "q0", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    zeros = np.zeros(n)
    traj = move_between_states(
        limits,
        start,
        as_vector(qd0, "qd0", n),
        state_or_zeros(qdd0, "qdd0", n),
        start,
        zeros,
        zeros,
        started=started,
        synchronization=synchronization,
        minimum_duration=None,
        check_limits=check_limits,
        joint_names=joint_names,
        interface="velocity",
    )
    # From Ruckig's own result: sampling ours would build the polynomials now.
    native = traj.metadata["native"]
    traj.metadata["stop_position"] = np.array(native.at_time(native.duration)[0], dtype=float)
    return traj
