r"""Sampling piecewise polynomials: times, rates and the joint states they give.

:meth:`Trajectory.sample <optraj.planners.trajectory.Trajectory.sample>` and
:meth:`~optraj.planners.trajectory.Trajectory.times` are built from these functions:
:func:`times_within` checks the times asked for, :func:`evaluate` runs Horner's scheme on the
segment each time falls in and :func:`hold_after_end` stills the state past the end;
:func:`sampling_rate` is the one rate rule of sampling and the checker, :func:`time_grid` lays
out evenly spaced times plus both sides of every breakpoint (for checking), and
:func:`uniform_times` the fixed-rate times of the exports (CSV, ROS), breakpoints left out.
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
    "hold_after_end",
    "sampling_rate",
    "time_grid",
    "times_within",
    "uniform_times",
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


def times_within(t: ArrayLike, duration: float, *, hold: bool = False) -> FloatArray:
    """One time or an array of times [s] as an array of shape (m,), checked against the duration.

    Times within :data:`TIME_TOLERANCE` of [0, duration] are clipped to it. With ``hold``,
    times past the end are accepted and returned as they are (see :func:`hold_after_end`).

    Raises:
        InvalidInputError: A time is not finite, lies before 0 by more than
            :data:`TIME_TOLERANCE`, or (without ``hold``) after the duration by more.
    """
    times = as_array(t, "t", ()) if ndim_of(t) == 0 else as_vector(t, "t")
    times = np.atleast_1d(times)
    early = times < -TIME_TOLERANCE
    late = times > duration + TIME_TOLERANCE
    outside = early if hold else early | late
    if np.any(outside):
        bad = float(times[outside][0])
        advice = "; sample(t, hold=True) holds the final state past the end" if bad > 0 else ""
        raise InvalidInputError(
            f"time {bad:.6g} s is outside the trajectory [0, {duration:.6g}] s{advice}",
            name="t",
            value=bad,
        )
    return np.where(late, times, np.clip(times, 0.0, duration))


def hold_after_end(values: list[FloatArray], past: NDArray[np.bool_]) -> list[FloatArray]:
    """Joint states past the end of a trajectory held still: every derivative zeroed there.

    Args:
        values: Positions then their derivatives (velocity, acceleration, jerk), each of
            shape (m, n), evaluated at the end time for the rows past the end.
        past: Which of the m rows lie past the end, shape (m,).

    Returns:
        ``values``, the derivative rows past the end set to 0 in place: the final position
        is held at rest, as a controller holds its last set point, even where the trajectory
        ends in motion (its velocity then jumps to 0 at the end).
    """
    for derivative in values[1:]:
        derivative[past] = 0.0
    return values


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


def uniform_times(duration: float, hz: float) -> FloatArray:
    """Times ``k / hz`` [s] for k = 0 .. floor(duration hz), and the end when it is off that grid.

    The fixed-rate times of the exports: ``floor(duration hz) + 1`` of them, one more when
    ``duration hz`` is not a whole number; no time is repeated and no breakpoint added. A grid
    time within :data:`TIME_TOLERANCE` of the end is the end itself (round-off of ``k / hz``).

    Args:
        duration: End time [s], > 0.
        hz: A rate already checked by :func:`sampling_rate`.
    """
    count = math.floor((duration + TIME_TOLERANCE) * hz)
    grid = np.arange(count + 1, dtype=float) / hz
    if count == 0 or duration - grid[-1] > TIME_TOLERANCE:
        return np.append(grid, duration)
    grid[-1] = duration
    return grid
