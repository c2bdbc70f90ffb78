r"""Sampling piecewise polynomials: times, rates and the joint states they give.

:meth:`Trajectory.sample <optraj.planners.trajectory.Trajectory.sample>` and
:meth:`~optraj.planners.trajectory.Trajectory.times` are built from these functions:
:func:`times_within` checks the times asked for, :func:`evaluate` runs Horner's scheme on the
segment each time falls in, :func:`sampling_rate` is the one rate rule of sampling and the
checker, and :func:`time_grid` lays out evenly spaced times plus both sides of every breakpoint.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.validation import MAX_COUNT, as_array, as_positive, as_vector, ndim_of

__all__ = [
    "MAX_RATE",
    "TIME_TOLERANCE",
    "TrajectorySample",
    "evaluate",
    "sampling_rate",
    "time_grid",
    "times_within",
]

FloatArray = NDArray[np.float64]

#: Times this far outside [0, duration] [s] are taken as the end point (round-off).
TIME_TOLERANCE = 1e-9
#: Highest sampling rate [Hz]: one sample per microsecond, the shortest duration
#: :func:`optraj.validation.as_duration` accepts (the checker's bound too).
MAX_RATE = 1e6


class TrajectorySample(NamedTuple):
    """Joint states at some times.

    Attributes:
        t: Times [s], shape (m,) (or a float for one time).
        q: Positions [rad or m], shape (m, n) (or (n,)).
        qd: Velocities [rad/s or m/s], same shape as q.
        qdd: Accelerations [rad/s^2 or m/s^2], same shape as q.
        jerk: Jerks [rad/s^3 or m/s^3], same shape as q.
    """

    t: FloatArray | float
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    jerk: FloatArray


def sampling_rate(rate: float, duration: float, dof: int) -> float:
    """``rate`` [Hz] checked for sampling ``dof`` joints over ``duration`` [s].

    All samples of every joint are held at once, so their number (instants times joints)
    is bounded by :data:`optraj.validation.MAX_COUNT`: q, qd, qdd and jerk are then at most
    320 MB.

    Raises:
        InvalidInputError: Not a number (bools refused), <= 0, above :data:`MAX_RATE`, or
            more sampled values than MAX_COUNT; the message names the rate that would fit.
    """
    hz = as_positive(rate, "rate", "Hz", maximum=MAX_RATE)
    samples = max(math.ceil(duration * hz), 1) + 1
    if samples * dof > MAX_COUNT:
        fits = (MAX_COUNT / dof - 1.0) / duration
        raise InvalidInputError(
            f"rate {hz:.6g} Hz over a {duration:.6g} s trajectory of {dof} joints needs "
            f"{samples * dof:.3g} sampled values, more than MAX_COUNT = {MAX_COUNT:.3g}; give "
            f"rate <= {fits:.6g} Hz",
            name="rate",
            value=rate,
        )
    return hz


def times_within(t: ArrayLike, duration: float) -> FloatArray:
    """One time or an array of times [s] as an array of shape (m,), clipped to [0, duration].

    Raises:
        InvalidInputError: A time is not finite or lies outside [0, duration] by more than
            :data:`TIME_TOLERANCE`.
    """
    times = as_array(t, "t", ()) if ndim_of(t) == 0 else as_vector(t, "t")
    times = np.atleast_1d(times)
    if times.size and (times.min() < -TIME_TOLERANCE or times.max() > duration + TIME_TOLERANCE):
        bad = times[(times < -TIME_TOLERANCE) | (times > duration + TIME_TOLERANCE)][0]
        raise InvalidInputError(
            f"time {bad:.6g} s is outside the trajectory [0, {duration:.6g}] s",
            name="t",
            value=bad,
        )
    return np.clip(times, 0.0, duration)


def evaluate(
    breakpoints: FloatArray, polynomials: list[FloatArray], times: FloatArray
) -> list[FloatArray]:
    """Values of piecewise polynomials at times within their breakpoints.

    At a breakpoint the segment that starts there is used (values are right-continuous),
    except at the final time.

    Args:
        breakpoints: Segment boundaries [s], shape (K + 1,).
        polynomials: Coefficient arrays, each of shape (K, d + 1, n) (d may differ).
        times: Times [s], shape (m,), within [breakpoints[0], breakpoints[-1]].

    Returns:
        One array of shape (m, n) per coefficient array.
    """
    segment = np.clip(np.searchsorted(breakpoints, times, side="right") - 1, 0, None)
    segment = np.minimum(segment, len(breakpoints) - 2)
    tau = (times - breakpoints[segment])[:, None]
    values = []
    for coeffs in polynomials:
        rows = coeffs[segment]  # (m, d + 1, n)
        result = rows[:, -1, :].copy()
        for i in range(rows.shape[1] - 2, -1, -1):
            result = result * tau + rows[:, i, :]
        values.append(result)
    return values


def time_grid(duration: float, hz: float, breakpoints: FloatArray | None = None) -> FloatArray:
    """Evenly spaced times at ``hz`` [Hz] from 0 to ``duration`` [s], both ends included.

    Args:
        duration: End time [s].
        hz: A rate already checked by :func:`sampling_rate`.
        breakpoints: When given, every breakpoint is added, and the time just before each
            inner one, so that a jump is seen from both sides.
    """
    count = max(math.ceil(duration * hz), 1)
    grid = np.linspace(0.0, duration, count + 1)
    if breakpoints is not None:
        inner = breakpoints[1:-1]
        before = np.maximum(inner - 1e-9 * max(duration, 1.0), 0.0)
        grid = np.unique(np.concatenate([grid, breakpoints, before]))
    return grid
