"""Quintics through via points: one C2 quintic per segment, through every via point exactly.

One quintic per segment, with the via velocities of Craig's heuristic (Craig, *Introduction to
Robotics*, 3rd ed., 2005, sec. 7.3: the mean of the adjacent slopes when they have the same
sign, else 0), limited so that each segment is monotone, and zero via accelerations: C2, at
rest at both ends, and never outside the range of its waypoints (so within the position
limits). Acceleration is zero at every via point, and the jerk jumps there.

Without given durations, :func:`quintic_fit` starts from each segment's rest-to-rest minimum
time, then rebalances and stretches the segments until the worst velocity or acceleration
peak, found exactly, sits on its limit. :func:`plan_quintic` makes the trajectory. Plan
through :class:`optraj.planners.ViaPoints` with profile ``"quintic"``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from optraj.planners.profiles.peak_bounds import position_range
from optraj.planners.profiles.peaks import extremes
from optraj.planners.profiles.via_segments import (
    ROUND_OFF,
    TimingIssue,
    floor_durations,
    limit_unit,
    segment_issues,
    segment_phases,
    worst_issue,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits

__all__ = [
    "MONOTONE_SLOPE_RATIO",
    "plan_quintic",
    "quintic_fit",
    "quintic_segments",
    "via_velocities",
]

FloatArray = NDArray[np.float64]

#: Most rebalancing rounds of :func:`quintic_fit`.
_ROUNDS = 40

#: Largest via velocity, as a multiple of an adjacent segment's slope, that keeps a quintic
#: with zero end accelerations monotone. With end velocities alpha and beta (times the slope)
#: its velocity is linear in them; on the square [0, c]^2 the worst corner is alpha = beta = c,
#: where qd(u) / slope = c - 30 (c - 1) u^2 (1 - u)^2 >= c - 30 (c - 1) / 16, which is >= 0
#: up to c = 15 / 7. (Our derivation; the same idea as Fritsch & Carlson's monotone cubics,
#: SIAM J. Numer. Anal. 17(2), 1980, whose bound is 3.)
MONOTONE_SLOPE_RATIO = 15.0 / 7.0


def via_velocities(points: FloatArray, h: FloatArray) -> FloatArray:
    """Velocities [rad/s or m/s] at every via point, shape (k, n); 0 at both ends.

    Craig's rule (2005, sec. 7.3): the mean of the adjacent segment slopes when they have the
    same sign, else 0. Each value is then limited to 15/7 of the smaller adjacent slope, so
    that every segment is monotone and the motion never leaves the range of its waypoints.
    """
    slopes = np.diff(points, axis=0) / h[:, None]
    left, right = slopes[:-1], slopes[1:]
    same = np.sign(left) * np.sign(right) > 0.0
    cap = MONOTONE_SLOPE_RATIO * np.minimum(np.abs(left), np.abs(right))
    inner = np.where(same, np.sign(left) * np.minimum(0.5 * np.abs(left + right), cap), 0.0)
    zero = np.zeros((1, points.shape[1]))
    return np.vstack([zero, inner, zero])


def quintic_segments(points: FloatArray, h: FloatArray) -> FloatArray:
    """One quintic per segment through the via points, C2, at rest at both ends.

    Each segment is the quintic Hermite interpolant of its end positions, the via velocities
    of :func:`via_velocities` and zero accelerations (so the accelerations agree at every via
    point and the whole is C2).

    Returns:
        b, shape (m, 6, n): segment i is ``sum_p b[i, p] u^p`` with ``u = (t - s_i) / h_i``.
    """
    velocity = via_velocities(points, h)
    p0, p1 = points[:-1], points[1:]
    v0 = velocity[:-1] * h[:, None]
    v1 = velocity[1:] * h[:, None]
    # Quintic Hermite with zero end accelerations on u in [0, 1] (end conditions solved in
    # closed form for the u^3, u^4, u^5 terms).
    dp = p1 - p0 - v0
    dv = v1 - v0
    b = np.zeros((h.size, 6, points.shape[1]))
    b[:, 0], b[:, 1] = p0, v0
    b[:, 3] = 10.0 * dp - 4.0 * dv
    b[:, 4] = -15.0 * dp + 7.0 * dv
    b[:, 5] = 6.0 * dp - 3.0 * dv
    return b


def _poly_derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients of d/du, shape (m, d, n)."""
    powers = np.arange(1, coefficients.shape[1], dtype=float)[None, :, None]
    return coefficients[:, 1:] * powers


def _poly_range(coefficients: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Smallest and largest value on u in [0, 1] of each polynomial (m, d + 1, n), exactly.

    Returns:
        (lowest, highest), each shape (m, n).
    """
    m, size, n = coefficients.shape
    low, high = extremes(coefficients.transpose(1, 0, 2).reshape(size, m * n), 1.0)
    return low.reshape(m, n), high.reshape(m, n)


def _abs_peak(coefficients: FloatArray) -> FloatArray:
    """Largest |p(u)| on [0, 1], shape (m, n)."""
    low, high = _poly_range(coefficients)
    return np.maximum(high, -low)


def _quintic_peaks(b: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Peak |velocity| [rad/s or m/s] and |acceleration| [rad/s^2 or m/s^2], shapes (m, n)."""
    slope = _poly_derivative(b)
    return (
        _abs_peak(slope) / h[:, None],
        _abs_peak(_poly_derivative(slope)) / h[:, None] ** 2,
    )


def _quintic_ratios(b: FloatArray, h: FloatArray, limits: JointLimits) -> FloatArray:
    """Per segment, the time stretch [-] that puts its worst joint exactly at a limit."""
    speed, accel = _quintic_peaks(b, h)
    ratio = np.maximum(speed / limits.velocity, np.sqrt(accel / limits.acceleration))
    return np.max(ratio, axis=1)


def _quintic_initial_durations(points: FloatArray, limits: JointLimits) -> FloatArray:
    """Per segment, the rest-to-rest quintic minimum time of its slowest joint [s].

    The rest-to-rest quintic peaks at 15/8 |d| / T in velocity and 10 / sqrt(3) |d| / T^2 in
    acceleration (Biagiotti & Melchiorri 2008, ch. 2); the search starts from there.
    """
    dist = np.abs(np.diff(points, axis=0))
    each = np.maximum(
        1.875 * dist / limits.velocity, np.sqrt(10.0 / math.sqrt(3.0) * dist / limits.acceleration)
    )
    return floor_durations(np.max(each, axis=1))


def quintic_fit(points: FloatArray, limits: JointLimits) -> FloatArray:
    """Segment durations [s] from the limits.

    Start from each segment's rest-to-rest minimum time, then stretch all segments by one
    factor c, which scales every velocity by 1/c and every acceleration by 1/c^2 exactly (the
    quintics' shapes in normalised time do not change), so that the worst peak sits on its
    limit. A few rounds then move time from segments below their limits to those at them
    (each segment stretched by the square root of its own peak ratio); a round is kept only
    when, after the uniform stretch, the whole move is shorter. (Stretching each segment
    until it is at its own limit need not converge: a segment's via velocities depend on its
    neighbours' durations.) A segment that does not move (a repeated waypoint between two
    stops) keeps a short hold, 1/1000 of the longest segment.
    """
    h = _quintic_initial_durations(points, limits)

    def stretched(durations: FloatArray) -> tuple[FloatArray, FloatArray]:
        ratio = _quintic_ratios(quintic_segments(points, durations), durations, limits)
        return durations * float(np.max(ratio)) * (1.0 + ROUND_OFF), ratio

    best, ratio = stretched(h)
    for _ in range(_ROUNDS):
        top = float(np.max(ratio))
        trial = h * np.sqrt(np.where(ratio > 0.0, ratio / top, 1.0))
        candidate, trial_ratio = stretched(trial)
        if np.sum(candidate) >= np.sum(best) * (1.0 - 1e-3):
            break
        h, best, ratio = trial, candidate, trial_ratio
    return best


def _quintic_issues(b: FloatArray, h: FloatArray, limits: JointLimits) -> list[TimingIssue]:
    """Velocity, acceleration and position limits broken by the quintics (worst per segment)."""
    speed, accel = _quintic_peaks(b, h)
    return [
        *segment_issues("velocity", speed, limits.velocity, limits),
        *segment_issues("acceleration", accel, limits.acceleration, limits),
        *_position_issues(b, limits),
    ]


def _position_issues(b: FloatArray, limits: JointLimits) -> list[TimingIssue]:
    """Segments whose quintic leaves the position limits (worst joint of each).

    Extremes are exact wherever the quintic may leave the limits by more than 1e-9
    (:func:`~optraj.planners.profiles.peak_bounds.position_range`), so the test below is exact.
    """
    m, size, n = b.shape
    low, high = position_range(
        b.transpose(1, 0, 2).reshape(size, m * n),
        1.0,
        np.tile(limits.lower, m),
        np.tile(limits.upper, m),
        1e-9,
    )
    lowest, highest = low.reshape(m, n), high.reshape(m, n)
    issues = []
    for i in range(b.shape[0]):
        above = highest[i] - limits.upper
        below = limits.lower - lowest[i]
        j = int(np.argmax(np.maximum(above, below)))
        if max(above[j], below[j]) > 1e-9:
            value = highest[i, j] if above[j] >= below[j] else lowest[i, j]
            bound = limits.upper[j] if above[j] >= below[j] else limits.lower[j]
            issues.append(
                TimingIssue(
                    "position",
                    f"segment {i + 1}",
                    j,
                    float(value),
                    float(bound),
                    limit_unit(limits, "position", j),
                    (i,),
                    math.inf,
                )
            )
    return issues


#: Appended to the error of a quintic that leaves the position limits.
_QUINTIC_HINT = (
    "; every segment is built monotone, so this should not happen: please report it with the "
    "waypoints"
)


def plan_quintic(
    points: FloatArray, durations: FloatArray | None, limits: JointLimits
) -> Trajectory:
    """Quintic-per-segment trajectory through the waypoints, from rest to rest.

    Args:
        points: Waypoints [rad or m], shape (k, n), k >= 2.
        durations: Segment durations [s], shape (k - 1,), or None to find them from the limits.
        limits: The joint limits.

    Returns:
        A degree-5 trajectory with phases ``segment 1`` ... ``segment k-1``; metadata
        ``profile``, ``segment_durations``, ``via_times``, ``via_velocities`` and
        ``via_accelerations``.

    Raises:
        InfeasibleError: The quintics break a velocity or acceleration limit (given durations)
            or leave the position limits; names the joint, the segment, the value and the limit.
    """
    h = quintic_fit(points, limits) if durations is None else durations
    b = quintic_segments(points, h)
    issues = _quintic_issues(b, h, limits)
    if issues:
        positions = [issue for issue in issues if issue.limit == "position"]
        worst = positions[0] if positions else worst_issue(issues)
        raise worst.error("quintic", limits.names, _QUINTIC_HINT if positions else "")
    powers = np.arange(6, dtype=float)[None, :, None]
    coefficients = b / h[:, None, None] ** powers
    times = np.concatenate([[0.0], np.cumsum(h)])
    metadata = {
        "profile": "quintic",
        "segment_durations": h,
        "via_times": times,
        "via_velocities": via_velocities(points, h),
        "via_accelerations": np.zeros_like(points),
    }
    return Trajectory(
        times,
        coefficients,
        joint_names=limits.names,
        phases=segment_phases(times),
        metadata=metadata,
    )
