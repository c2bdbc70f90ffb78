"""Checks shared by the problem dataclasses."""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, JointLimitError
from optraj.robots import JointLimits, Robot
from optraj.validation import as_number, as_positive, as_vector

__all__ = [
    "MAX_TOOL_SPEED",
    "check_robot",
    "checked_positions",
    "checked_state",
    "joint_state",
    "non_negative",
    "normal_pair",
    "positive",
    "positive_fields",
    "resolve_limits",
    "unit_vector",
]

FloatArray = NDArray[np.float64]

#: Fastest tool speed a problem may command [m/s] (a strike's cue or paddle speed, a
#: Cartesian line's speed): the speed of sound in dry air at 20 degC, about 343 m/s. No arm
#: moves a tool that fast (the shipped arms' joint speed limits allow a few m/s at the tool),
#: and up to it the strike maths stays finite, where a speed of 1e308 m/s overflowed.
MAX_TOOL_SPEED = 343.0


def check_robot(robot: object, wanted: str | None = None) -> Robot:
    """Return ``robot`` if it is a :class:`robots.Robot` (named ``wanted`` when given)."""
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot (from robots.load), got {type(robot).__name__}",
            name="robot",
        )
    if wanted is not None and robot.name != wanted:
        raise InvalidInputError(
            f"this problem needs the {wanted!r} robot, got {robot.name!r}", name="robot"
        )
    return robot


def positive(value: float, name: str, unit: str, maximum: float | None = None) -> float:
    """``value`` as a finite float > 0 (and <= ``maximum`` [unit] if given), or a typed error.

    Delegates to :func:`optraj.validation.as_positive`: no bool or string passes as a number.
    """
    return as_positive(value, name, unit, maximum=maximum)


def positive_fields(problem: object, units: dict[str, str]) -> None:
    """Set each named field of a frozen problem to its value as :func:`positive` checks it.

    ``units`` maps field names to their units, for the message.
    """
    for name, unit in units.items():
        object.__setattr__(problem, name, positive(getattr(problem, name), name, unit))


def non_negative(value: float, name: str, unit: str, maximum: float | None = None) -> float:
    """``value`` as a finite float >= 0 (and <= ``maximum`` [unit] if given), or a typed error.

    Delegates to :func:`optraj.validation.as_number`: no bool or string passes as a number.
    """
    return as_number(value, name, unit, minimum=0.0, maximum=maximum)


def unit_vector(value: ArrayLike, name: str) -> FloatArray:
    """``value`` (shape (3,)) scaled to unit length; a zero vector is an error."""
    vector = as_vector(value, name, 3)
    norm = float(np.linalg.norm(vector))
    if norm < 1e-9:
        raise InvalidInputError(f"{name} must be a non-zero direction, got {vector}", name=name)
    return vector / norm


def normal_pair(direction: FloatArray) -> FloatArray:
    """Two unit vectors completing a unit ``direction`` to an orthonormal basis, shape (2, 3).

    The first is normal to the direction and to the world axis it is least aligned with; the
    second is ``direction x first``.
    """
    helper = np.eye(3)[int(np.argmin(np.abs(direction)))]
    first = np.cross(direction, helper)
    first /= np.linalg.norm(first)
    return np.array([first, np.cross(direction, first)])


def joint_state(
    limits: JointLimits,
    q: ArrayLike | None,
    qd: ArrayLike | None,
    qdd: ArrayLike | None,
    label: str,
) -> tuple[FloatArray | None, FloatArray, FloatArray | None]:
    """Validate a joint state against the limits; a missing velocity means rest.

    Returns:
        (q or None, qd, qdd or None), each shape (n,).

    Raises:
        JointLimitError: A position, speed or acceleration beyond its limit.
        InvalidInputError: Wrong shape or non-finite values.
    """
    position = None if q is None else as_vector(q, f"q_{label}", limits.n)
    velocity, acceleration = checked_state(limits, position, qd, qdd, label)
    return position, velocity, acceleration


#: NumPy's float64 type, compared by identity on the fast paths of the state checks.
_FLOAT64 = np.dtype(np.float64)


def checked_positions(
    limits: JointLimits, q_start: object, q_goal: object
) -> tuple[FloatArray, FloatArray] | None:
    """Copies of two float64 position vectors when both lie within the position limits.

    The common case of a problem's start and goal, checked in one pass over Python floats
    (within the limits by 1e-9 implies finite, see :meth:`JointLimits.within_positions`).

    Returns:
        The two positions as new arrays, or None when either is anything else (another
        type, shape or dtype, or out of the limits): then :func:`joint_state`'s checks give
        the result or the error.
    """
    n = limits.n
    for value in (q_start, q_goal):
        if not (
            type(value) is np.ndarray
            and value.dtype is _FLOAT64
            and value.shape == (n,)
            and limits.within_positions(value.tolist(), 1e-9)
        ):
            return None
    return cast(FloatArray, q_start).copy(), cast(FloatArray, q_goal).copy()


def checked_state(
    limits: JointLimits,
    position: FloatArray | None,
    qd: ArrayLike | None,
    qdd: ArrayLike | None,
    label: str,
) -> tuple[FloatArray, FloatArray | None]:
    """:func:`joint_state` for a position already checked to be a finite vector of length n.

    Returns:
        (qd, qdd or None), each shape (n,); qd is zeros when None (rest).

    Raises:
        As :func:`joint_state`.
    """
    n = limits.n
    if position is not None and not limits.within_positions(position.tolist(), 1e-9):
        limits.check_position(position, tolerance=1e-9, context=f"q_{label}")
    fast_velocity = None if qd is None else _rate_within(limits, qd, "velocity")
    fast_acceleration = None if qdd is None else _rate_within(limits, qdd, "acceleration")
    if (qd is None or fast_velocity is not None) and (qdd is None or fast_acceleration is not None):
        # rest (zeros) is within every limit
        return (np.zeros(n) if fast_velocity is None else fast_velocity), fast_acceleration
    # the checks one by one, for the first error in this order
    velocity = np.zeros(n) if qd is None else as_vector(qd, f"qd_{label}", n)
    acceleration = None if qdd is None else as_vector(qdd, f"qdd_{label}", n)
    for values, bound, quantity in (
        (None if qd is None else velocity, limits.velocity, "velocity"),  # rest is within
        (acceleration, limits.acceleration, "acceleration"),
    ):
        if values is None or limits.within_symmetric(quantity, values.tolist(), 1e-9):
            continue
        excess = np.abs(values) - bound
        worst = int(np.argmax(excess))
        if excess[worst] > 1e-9:
            raise JointLimitError(
                limits.names[worst],
                values[worst],
                -bound[worst],
                bound[worst],
                quantity=quantity,
                unit=limits.unit(quantity, worst),
                context=f"{quantity} at the {label}",
            )
    return velocity, acceleration


def _rate_within(limits: JointLimits, value: object, quantity: str) -> FloatArray | None:
    """A copy of a float64 vector of n rates within their symmetric limits by 1e-9, else None.

    Within implies finite (see :meth:`JointLimits.within_symmetric`).
    """
    if (
        type(value) is np.ndarray
        and value.dtype is _FLOAT64
        and value.shape == (limits.n,)
        and limits.within_symmetric(quantity, value.tolist(), 1e-9)
    ):
        return value.copy()
    return None


def resolve_limits(robot: Robot, limits: JointLimits | None) -> JointLimits:
    """The limits to plan for: ``limits`` if given (for the robot's joints), else the robot's."""
    if limits is None:
        return robot.limits
    if not isinstance(limits, JointLimits) or limits.names != robot.joint_names:
        raise InvalidInputError(
            f"limits must be a robots.JointLimits for the joints {robot.joint_names}",
            name="limits",
        )
    return limits
