"""The checker's one round-off rule, and the allowance of a prescribed boundary state.

Every comparison the checker makes (a limit, a jump, a boundary state) allows the same
round-off, :func:`round_off`; planners that promise to pass the checker use it too
(Ruckig's conversion, validation and limit scan, and the lower bound in
:mod:`planners.time_optimal`). :func:`state_allowance` applies it to a
prescribed start or end state.

Example::

    slack = round_off(limits.velocity, slope=qdd, duration=trajectory.duration)
    passes = np.abs(qd) <= limits.velocity + slack
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.robots import JointLimits

__all__ = [
    "ABSOLUTE_SLACK",
    "RELATIVE_SLACK",
    "TIME_ROUND_OFF",
    "round_off",
    "state_allowance",
    "thresholds",
]

FloatArray = NDArray[np.float64]

#: The round-off rule, one for every comparison the checker makes (and for the planners that
#: promise to pass it, e.g. :mod:`planners.time_optimal.ruckig_planner`): a computed value is
#: taken to meet a bound, or to equal another value, when it misses by at most
#: :func:`round_off`, i.e.
#: ``RELATIVE_SLACK * scale + ABSOLUTE_SLACK + TIME_ROUND_OFF * max(1, T) * |slope|``: a
#: relative error of the value (scale: the limit, the range, or the magnitudes summed to
#: compute it) plus the change of the value over the round-off of the time at which it is
#: computed (a breakpoint of a 574 s trajectory is known to about 1e-13 s, over which an
#: acceleration ramping at 559 rad/s^3 changes by 6e-11 rad/s^2).
RELATIVE_SLACK = 1e-9
#: Absolute part of the round-off rule [unit of the quantity].
ABSOLUTE_SLACK = 1e-12
#: Round-off of a time [s] per second of duration (at least 1 s): 64 machine epsilons, room
#: for a breakpoint that is a sum of a few dozen rounded durations. Breakpoints that come
#: closer than this are one instant
#: (:func:`planners.time_optimal.ruckig_planner.native_to_trajectory` merges them).
TIME_ROUND_OFF = 64.0 * float(np.finfo(float).eps)


def round_off(scale: ArrayLike, slope: ArrayLike = 0.0, duration: float = 1.0) -> FloatArray:
    """The round-off allowed on a computed value (the checker's one rule for all comparisons).

    Args:
        scale: Scale of the value [unit]: its limit, range, or the magnitudes summed to get it.
        slope: Time derivative of the value where it is computed [unit/s].
        duration: Duration of the trajectory [s]; times are known to
            ``TIME_ROUND_OFF * max(1, duration)``.

    Returns:
        ``RELATIVE_SLACK * |scale| + ABSOLUTE_SLACK + TIME_ROUND_OFF * max(1, duration) * |slope|``
        [unit], broadcast over ``scale`` and ``slope``.
    """
    resolution = TIME_ROUND_OFF * max(1.0, float(duration))
    return (
        RELATIVE_SLACK * np.abs(np.asarray(scale, dtype=float))
        + ABSOLUTE_SLACK
        + resolution * np.abs(np.asarray(slope, dtype=float))
    )


def thresholds(limits: JointLimits) -> list[FloatArray]:
    """Round-off scales per derivative order: position range, velocity and acceleration limits.

    Args:
        limits: The joint limits.

    Returns:
        Three arrays of shape (n,): ``upper - lower`` [rad or m], ``velocity``,
        ``acceleration``.
    """
    return [limits.upper - limits.lower, limits.velocity, limits.acceleration]


def state_allowance(
    wanted: Sequence[FloatArray | None],
    slopes: Sequence[FloatArray],
    tolerance: float,
    limits: JointLimits,
    duration: float,
) -> list[FloatArray | None]:
    """How far each prescribed boundary quantity may be missed: the tolerance plus round-off.

    One rule for the ``start state`` / ``end state`` finding and for the boundary jumps, so
    that a state that passes the finding is never a jump (and one that fails it always is,
    for velocity and acceleration); planners that promise to pass the checker use it too.

    Args:
        wanted: The prescribed q, qd, qdd (None where not prescribed), each shape (n,).
        slopes: The trajectory's qd, qdd, jerk at that end, each shape (n,).
        tolerance: The state's tolerance [unit of each quantity].
        limits: The limits (round-off scales).
        duration: Trajectory duration [s].

    Returns:
        Per order, the largest deviation that passes, shape (n,), or None where nothing is
        prescribed: ``tolerance + round_off(scale + |wanted|, slope, duration)``, the scale
        being the position range, the velocity or the acceleration limit.
    """
    scales = thresholds(limits)
    return [
        None
        if target is None
        else tolerance + round_off(scales[order] + np.abs(target), slopes[order], duration)
        for order, target in enumerate(wanted)
    ]
