"""Checks of what a Ruckig move is given: options, limits and boundary states.

Ruckig itself reports a target state out of reach only with a terse message, and takes a
start state beyond the limits as one to brake from; the functions here refuse such inputs
first, with typed errors that name the joint and the values (:class:`InfeasibleError`,
:class:`InvalidInputError`, :class:`UnknownNameError`). They serve
:func:`~planners.time_optimal.ruckig_move.state_to_state`, :class:`Ruckig`,
:class:`OnlineRuckig` and :func:`~planners.time_optimal.lower_bound.lower_bound` alike.

States are judged as the checker judges a finished trajectory (its round-off slack,
:data:`planners.checker.RELATIVE_SLACK` and :data:`planners.checker.ABSOLUTE_SLACK`) when they
are left, and strictly, as Ruckig judges them, when they are to be reached.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import cast

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.checker import ABSOLUTE_SLACK, RELATIVE_SLACK
from optraj.robots import JointLimits
from optraj.validation import as_duration, as_vector

__all__ = [
    "SYNCHRONIZATIONS",
    "check_boundary_states",
    "check_state",
    "check_unsynchronised",
    "checked_limits",
    "longest_minimum_duration",
    "result_joint_names",
    "state_or_zeros",
    "synchronization_option",
]

FloatArray = NDArray[np.float64]

#: Synchronisation names accepted here and Ruckig's matching options: ``time`` (every joint
#: starts and ends together), ``phase`` (also on a straight line in joint space when the
#: states allow it, else as ``time``), ``time_if_necessary`` (only joints that end moving
#: are synchronised) and ``none`` (every joint at its own fastest; a joint that arrives
#: early rests there, so ``none`` needs a target at rest).
SYNCHRONIZATIONS: Mapping[str, ruckig.Synchronization] = {
    "time": ruckig.Synchronization.Time,
    "phase": ruckig.Synchronization.Phase,
    "time_if_necessary": ruckig.Synchronization.TimeIfNecessary,
    "none": ruckig.Synchronization.No,
}


def synchronization_option(name: str) -> ruckig.Synchronization:
    """Ruckig's synchronisation option for a name of :data:`SYNCHRONIZATIONS`.

    Raises:
        UnknownNameError: Any other name; the message lists the known ones.
    """
    if not isinstance(name, str) or name not in SYNCHRONIZATIONS:
        raise UnknownNameError("synchronization", str(name), SYNCHRONIZATIONS)
    return SYNCHRONIZATIONS[name]


def check_unsynchronised(name: str, qd1: FloatArray, qdd1: FloatArray) -> None:
    """Refuse ``none`` with a moving target: early joints would move on past their target.

    Ruckig lets a joint that arrives before the others continue with its target velocity
    and acceleration, so the move would not end in the target state.

    Args:
        name: The synchronisation name.
        qd1: Target velocities [rad/s or m/s], shape (n,).
        qdd1: Target accelerations [rad/s^2 or m/s^2], shape (n,).

    Raises:
        InvalidInputError: ``name`` is ``none`` and the target is not at rest.
    """
    if name == "none" and (np.any(qd1 != 0.0) or np.any(qdd1 != 0.0)):
        raise InvalidInputError(
            "synchronization 'none' needs a target at rest: a joint that arrives early would "
            "move on with its target velocity and acceleration; use 'time_if_necessary' to "
            "synchronise only the joints that end moving",
            name="synchronization",
        )


def longest_minimum_duration(*values: float | None) -> float | None:
    """The largest of the given minimum durations [s], or None when none is given.

    Raises:
        InvalidInputError: A value that is not a duration in [MIN_DURATION, MAX_DURATION]
            seconds (:func:`optraj.validation.as_duration`).
    """
    found: list[float] = []
    for value in values:
        if value is not None:
            found.append(as_duration(value, "minimum_duration"))
    return max(found) if found else None


def result_joint_names(joint_names: Sequence[str] | None, limits: JointLimits) -> tuple[str, ...]:
    """A result's joint names: those of ``limits`` when None, else n strings.

    Raises:
        InvalidInputError: Not a sequence of ``limits.n`` strings (a single string is refused:
            its characters are not names).
    """
    if joint_names is None:
        return limits.names
    names = None if isinstance(joint_names, str) else _as_tuple(joint_names)
    if names is None or len(names) != limits.n or not all(isinstance(x, str) for x in names):
        raise InvalidInputError(
            f"joint_names must be a sequence of {limits.n} strings, got {joint_names!r}",
            name="joint_names",
        )
    return cast(tuple[str, ...], names)  # every item was just checked to be a str


def _as_tuple(values: object) -> tuple[object, ...] | None:
    """``values`` as a tuple, or None when it is not iterable."""
    try:
        return tuple(cast(Iterable[object], values))
    except TypeError:
        return None


def checked_limits(limits: object) -> JointLimits:
    """``limits`` if it is a :class:`robots.JointLimits`, else InvalidInputError."""
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(
            f"limits must be a robots.JointLimits, got {type(limits).__name__}", name="limits"
        )
    return limits


def state_or_zeros(value: ArrayLike | None, name: str, n: int) -> FloatArray:
    """A state vector of length n; zeros when None."""
    return np.zeros(n) if value is None else as_vector(value, name, n)


def check_state(
    qd: FloatArray, qdd: FloatArray, limits: JointLimits, label: str, *, arriving: bool
) -> None:
    """Raise InfeasibleError if a velocity/acceleration state is outside what the limits allow.

    Beyond the box limits, a state is out of reach when the velocity it implies while the
    acceleration ramps to or from zero at the jerk limit breaks the velocity limit: leaving a
    start state with acceleration a, the velocity still changes by a^2 / (2 j) in the sign of
    a; arriving at a target with acceleration a, it was a^2 / (2 j) further the other way.

    Args:
        qd: Velocities [rad/s or m/s], shape (n,).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (n,).
        limits: Joint limits.
        label: ``"start"`` or ``"target"``.
        arriving: Whether the state is reached (target) rather than left (start). Targets
            are judged strictly, as Ruckig judges them; starts with round-off slack, as
            the finished trajectory is.
    """
    velocities, accelerations = qd.tolist(), qdd.tolist()
    if _state_within(velocities, accelerations, limits, arriving):
        return
    floats = limits.floats
    states = zip(velocities, accelerations, strict=True)
    # Python floats: seven joints cost less this way than in NumPy calls.
    for j, (velocity, acceleration) in enumerate(states):
        speed_limit = floats["velocity"][j]
        velocity_bound = (
            speed_limit if arriving else speed_limit * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
        )
        swing = acceleration * abs(acceleration) / (2.0 * floats["jerk"][j])
        implied = velocity - swing if arriving else velocity + swing
        for quantity, value, allowed in (
            ("velocity", velocity, speed_limit),
            ("acceleration", acceleration, floats["acceleration"][j]),
        ):
            bound = allowed if arriving else allowed * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
            if abs(value) > bound:
                raise InfeasibleError(
                    f"{label} {quantity} {value:.6g} {limits.unit(quantity, j)} of joint "
                    f"{limits.names[j]!r} exceeds its limit {allowed:.6g} "
                    f"{limits.unit(quantity, j)}",
                    limit=quantity,
                    joint=limits.names[j],
                    required=abs(value),
                    allowed=allowed,
                )
        if abs(implied) > velocity_bound:
            when = "before it arrives at" if arriving else "after it leaves"
            raise InfeasibleError(
                f"joint {limits.names[j]!r} reaches a velocity of {implied:.6g} "
                f"{limits.unit('velocity', j)} {when} its {label} state (velocity "
                f"{velocity:.6g}, acceleration {acceleration:.6g}) with jerk limit "
                f"{floats['jerk'][j]:.6g}; its velocity limit is {speed_limit:.6g}",
                limit="velocity",
                joint=limits.names[j],
                required=abs(implied),
                allowed=speed_limit,
            )


def _state_within(
    velocities: list[float], accelerations: list[float], limits: JointLimits, arriving: bool
) -> bool:
    """Whether :func:`check_state` passes the state: its three tests, without the messages.

    The same arithmetic, joint by joint, so that the verdict is the same; the caller runs
    the full checks only when this says no, for the error.
    """
    floats = limits.floats
    if not any(accelerations):  # then the implied velocity is the velocity itself
        speed_limits = floats["velocity"]
        if arriving:
            return all(abs(v) <= limit for v, limit in zip(velocities, speed_limits, strict=True))
        return all(
            abs(v) <= limit * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
            for v, limit in zip(velocities, speed_limits, strict=True)
        )
    for velocity, acceleration, speed_limit, acceleration_limit, jerk_limit in zip(
        velocities,
        accelerations,
        floats["velocity"],
        floats["acceleration"],
        floats["jerk"],
        strict=True,
    ):
        if arriving:
            velocity_bound, acceleration_bound = speed_limit, acceleration_limit
        else:
            velocity_bound = speed_limit * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
            acceleration_bound = acceleration_limit * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
        swing = acceleration * abs(acceleration) / (2.0 * jerk_limit)
        implied = velocity - swing if arriving else velocity + swing
        if (
            abs(velocity) > velocity_bound
            or abs(acceleration) > acceleration_bound
            or abs(implied) > velocity_bound
        ):
            return False
    return True


def check_boundary_states(
    limits: JointLimits,
    start: tuple[FloatArray, FloatArray] | None,
    target: tuple[FloatArray, FloatArray],
) -> None:
    """:func:`check_state` on a move's start state (unless None), then on its target state.

    Args:
        limits: Joint limits.
        start: Start velocities and accelerations, each shape (n,), or None to leave the
            start unchecked (Ruckig brakes a start beyond the limits back within them).
        target: Target velocities and accelerations, each shape (n,).

    Raises:
        InfeasibleError: A state outside what the limits allow (see :func:`check_state`).
    """
    if start is not None:
        check_state(*start, limits, "start", arriving=False)
    check_state(*target, limits, "target", arriving=True)
