r"""Multi-segment motion through via points, with blends: ``mstraj`` in the Toolbox's shape.

Every axis moves on straight lines between the via points, all axes arriving together, and
changes velocity on a quintic blend of ``tacc`` centred on each inner via point (so the blend
cuts the corner: it passes the via point at :math:`\tfrac{3}{32} t_{acc} (v_{out} - v_{in})`
from it). The motion starts at q0 with velocity qd0 and ends on the last via point with
velocity qdf, each through a blend of ``tacc / 2``. Each blend is the quintic of
:func:`~optraj.planners.profiles.polynomial_coefficients.quintic_coefficients` meeting the
lines' positions and velocities with zero end accelerations, as the Robotics Toolbox's blends
are ``jtraj`` moves.

Segment times follow the Robotics Toolbox's rules: ``tacc`` is rounded up to a whole number of
steps ``dt``; given ``qdmax``, a segment lasts its slowest axis's ``|dq| / qdmax`` rounded up to
whole steps plus the blend time (half of it on the first segment), and at least ``2 tacc``;
given ``tsegment``, those times. Unlike the Robotics Toolbox, whose first sample is the state
at ``dt`` (labelled 0), the samples here are the states at 0, dt, 2 dt, ... and at the end,
labelled with their own times, and velocities and accelerations are given.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import TimeBase
from optraj.planners.arrays.result import SampledProfile, sample_fields
from optraj.planners.base import stamp
from optraj.planners.profiles.polynomial_coefficients import quintic_coefficients
from optraj.planners.profiles.via_segments import segment_phases
from optraj.planners.trajectory import Trajectory
from optraj.validation import (
    MAX_COUNT,
    MAX_DURATION,
    MIN_DURATION,
    as_array,
    as_duration,
    as_number,
    as_vector,
    ndim_of,
)

__all__ = ["MultiSegmentProfile", "SegmentInfo", "mstraj"]

FloatArray = NDArray[np.float64]

#: Round-off allowed when rounding a time up to whole steps, as a fraction of a step.
_STEP_ROUND_OFF = 1e-9
#: Pieces shorter than this fraction of the duration are dropped (zero-length blends, lines
#: fully covered by their blends).
_GAP = 1e-12


class SegmentInfo(NamedTuple):
    """How one segment was timed.

    Attributes:
        slowest: The axis whose ``|dq| / qdmax`` set the segment time, or None when
            ``tsegment`` gave it.
        segtime: Segment time [s], via point to via point.
        clock: When the segment's motion starts [s]: 0 for the first, else the start of the
            blend into it.
    """

    slowest: int | None
    segtime: float
    clock: float


@dataclass(frozen=True, repr=False)
class MultiSegmentProfile(SampledProfile):
    """A multi-segment profile's samples, with its via points and timing.

    Attributes:
        arrive: Planned arrival time at each via point [s], shape (k,) (the lines pass the
            inner ones then; the blends cut them).
        via: The via points [rad or m], shape (k, n), without the start.
        info: How each segment was timed.
    """

    arrive: FloatArray
    via: FloatArray
    info: tuple[SegmentInfo, ...]

    def __post_init__(self) -> None:
        super().__post_init__()
        self.arrive.setflags(write=False)
        self.via.setflags(write=False)


def _whole_steps(value: FloatArray, dt: float) -> FloatArray:
    """``value`` [s] rounded up to whole steps ``dt`` [s] (round-off below a step ignored)."""
    return np.ceil(value / dt - _STEP_ROUND_OFF) * dt


def _blend_times(tacc: float | ArrayLike, segments: int, dt: float) -> FloatArray:
    """Blend time per segment [s], shape (segments,), >= 0, in whole steps."""
    if ndim_of(tacc) == 0:
        value = as_number(tacc, "tacc", "s", minimum=0.0)
        times = np.full(segments, value)
    else:
        times = as_vector(tacc, "tacc", segments)
        if np.any(times < 0.0):
            raise InvalidInputError(f"tacc must be >= 0 s, got {times}", name="tacc")
    return _whole_steps(times, dt)


def _speed_limits(qdmax: float | ArrayLike, n: int) -> FloatArray:
    """Speed per axis [unit of q per s], shape (n,), > 0."""
    speeds = np.full(n, as_number(qdmax, "qdmax")) if ndim_of(qdmax) == 0 else None
    if speeds is None:
        speeds = as_vector(qdmax, "qdmax", n)
    if np.any(speeds <= 0.0):
        raise InvalidInputError(f"qdmax must be > 0 for every axis, got {speeds}", name="qdmax")
    return speeds


def _halves(tacc: FloatArray) -> FloatArray:
    """Half-blend at each via point [s], shape (k + 1,): start, inner ones, end."""
    return 0.5 * np.concatenate([tacc, tacc[-1:]])


def _segment_times(
    points: FloatArray,
    dt: float,
    tacc: FloatArray,
    qdmax: float | ArrayLike | None,
    tsegment: ArrayLike | None,
) -> tuple[FloatArray, list[int | None]]:
    """Each segment's time [s] and the axis that set it (None when ``tsegment`` gave it)."""
    segments = points.shape[0] - 1
    room = _halves(tacc)[:-1] + _halves(tacc)[1:]  # the blends each segment holds
    if qdmax is not None and tsegment is not None:
        raise InvalidInputError("give qdmax or tsegment, not both", name="qdmax")
    if tsegment is not None:
        times = as_vector(tsegment, "tsegment", segments)
        short = np.flatnonzero((times < MIN_DURATION) | (times < room * (1.0 - _GAP)))
        if short.size:
            i = int(short[0])
            raise InvalidInputError(
                f"tsegment[{i}] = {times[i]:.6g} s is too short: it must be >= "
                f"{MIN_DURATION:.6g} s and hold its blends, at least {room[i]:.6g} s (half the "
                f"blend time at each end)",
                name="tsegment",
                value=tsegment,
            )
        return times, [None] * segments
    if qdmax is None:
        raise InvalidInputError(
            "give qdmax (axis speeds) or tsegment (segment times)", name="tsegment"
        )
    speeds = _speed_limits(qdmax, points.shape[1])
    lead = tacc.copy()
    lead[0] = _whole_steps(np.array([0.5 * tacc[0]]), dt)[0]  # the first blend is half
    with np.errstate(over="ignore"):  # an infinite time is refused by the caller
        needed = lead[:, None] + _whole_steps(np.abs(np.diff(points, axis=0)) / speeds, dt)
    slowest: list[int | None] = [int(j) for j in np.argmax(needed, axis=1)]
    times = np.maximum.reduce([np.max(needed, axis=1), 2.0 * tacc, room, np.full(segments, dt)])
    return times, slowest


def _pieces(
    points: FloatArray, h: FloatArray, tacc: FloatArray, v0: FloatArray, vf: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Breakpoints (K + 1,) and quintic coefficients (K, 6, n) of lines and blends."""
    k = points.shape[0]
    via = np.concatenate([[0.0], np.cumsum(h)])
    T = float(via[-1])
    line = np.diff(points, axis=0) / h[:, None]  # (k - 1, n)
    half = _halves(tacc)
    # Velocities into and out of each via point: qd0 before the start, qdf after the end.
    into = np.vstack([v0, line])
    out = np.vstack([line, vf])
    n = points.shape[1]
    pieces: list[tuple[float, float, FloatArray]] = []  # (start, end, coefficients (6, n))
    for i in range(k):
        # The blend about via point i, from the line before it to the line after it; at the
        # start and end, one-sided: from the start state, or onto the last via point.
        start, end = max(via[i] - half[i], 0.0), min(via[i] + half[i], T)
        q_start = points[i] - (via[i] - start) * into[i]
        q_end = points[i] + (end - via[i]) * out[i]
        if end > start:
            blend = quintic_coefficients(q_start, q_end, end - start, into[i], out[i])
            pieces.append((start, end, blend))
        if i < k - 1:  # the line of segment i, between its blends
            a, b = via[i] + half[i], via[i + 1] - half[i + 1]
            rows = np.zeros((6, n))
            rows[0], rows[1] = points[i] + half[i] * line[i], line[i]
            pieces.append((a, b, rows))
    kept = [piece for piece in pieces if piece[1] - piece[0] > _GAP * T]
    breakpoints = np.array([piece[0] for piece in kept] + [T])
    breakpoints[0] = 0.0
    coefficients = np.stack([piece[2] for piece in kept])
    return breakpoints, coefficients


def _sample_times(duration: float, dt: float, n: int) -> TimeBase:
    """Times 0, dt, 2 dt, ... up to ``duration`` [s], and ``duration`` itself."""
    steps = math.floor(duration / dt + _STEP_ROUND_OFF)
    if (steps + 2) * n > MAX_COUNT:
        raise InvalidInputError(
            f"dt = {dt:.6g} s gives {steps + 1} samples of {n} axes over {duration:.6g} s; at "
            f"most {MAX_COUNT} values: make dt larger",
            name="dt",
            value=dt,
        )
    times = np.minimum(dt * np.arange(steps + 1), duration)
    if duration - times[-1] > _STEP_ROUND_OFF * dt:
        times = np.append(times, duration)
    times[-1] = duration
    return TimeBase(times, duration, True)


def _via_points(viapoints: ArrayLike, q0: ArrayLike | None) -> tuple[FloatArray, FloatArray]:
    """The start and every via point as rows, shape (k + 1, n), and the via points alone."""
    rows = as_array(viapoints, "viapoints", (None, None))
    n = rows.shape[1]
    points = rows if q0 is None else np.vstack([as_vector(q0, "q0", n), rows])
    if points.shape[0] < 2 or n < 1:
        raise InvalidInputError(
            f"viapoints must hold at least one axis and two rows (one with q0), got shape "
            f"{rows.shape}",
            name="viapoints",
        )
    return points, points[1:].copy()


def mstraj(
    viapoints: ArrayLike,
    dt: float,
    tacc: float | ArrayLike,
    qdmax: float | ArrayLike | None = None,
    tsegment: ArrayLike | None = None,
    q0: ArrayLike | None = None,
    qd0: ArrayLike | None = None,
    qdf: ArrayLike | None = None,
) -> MultiSegmentProfile:
    """Multi-segment, multi-axis motion through via points: lines joined by quintic blends.

    Args:
        viapoints: Via points [rad or m, any unit per axis], shape (k, n), one per row; the
            first row is the start unless q0 is given.
        dt: Sample period [s], in [MIN_DURATION, MAX_DURATION].
        tacc: Blend time [s], >= 0, rounded up to whole steps: one for every blend, or one
            per segment, shape (segments,) (the blend into segment i; the last one's half
            ends the motion).
        qdmax: Axis speed [unit of q per s], > 0: one for all axes or shape (n,); gives the
            segment times. Exactly one of qdmax and tsegment.
        tsegment: Segment times [s], shape (segments,), each > 0 and holding its blends.
        q0: Start [unit of q], shape (n,); None: the first row of viapoints.
        qd0: Start velocity [unit of q per s], shape (n,); None: zero.
        qdf: End velocity [unit of q per s], shape (n,); None: zero.

    Returns:
        Samples at 0, dt, 2 dt, ... and the end (shape (m, n) each), the Trajectory (phases
        ``segment 1`` ...), ``arrive``, ``via`` and ``info``.

    Raises:
        InvalidInputError: Both or neither of qdmax and tsegment, arrays of the wrong shape,
            values that are not finite, dt < 1e-6 s, tacc < 0, qdmax <= 0, a segment time too
            short for its blends, or more samples than MAX_COUNT values; the message names
            the argument and the bound.
    """
    started = time.perf_counter()
    points, via = _via_points(viapoints, q0)
    n = points.shape[1]
    step = as_duration(dt, "dt")
    v0 = np.zeros(n) if qd0 is None else as_vector(qd0, "qd0", n)
    vf = np.zeros(n) if qdf is None else as_vector(qdf, "qdf", n)
    blends = _blend_times(tacc, points.shape[0] - 1, step)
    h, slowest = _segment_times(points, step, blends, qdmax, tsegment)
    if float(np.sum(h)) > MAX_DURATION:
        raise InvalidInputError(
            f"the motion would last {np.sum(h):.6g} s, more than {MAX_DURATION:.6g} s: "
            f"raise qdmax or shorten tsegment",
            name="qdmax" if tsegment is None else "tsegment",
        )
    breakpoints, coefficients = _pieces(points, h, blends, v0, vf)
    arrive = np.cumsum(h)
    traj = stamp(
        Trajectory(
            breakpoints, coefficients, phases=segment_phases(np.concatenate([[0.0], arrive]))
        ),
        "mstraj",
        started,
        time_unit="s",
        segment_times=h,
        blend_times=blends,
    )
    clock = np.concatenate([[0.0], arrive[:-1] - 0.5 * blends[1:]])
    info = tuple(
        SegmentInfo(axis, float(length), float(c))
        for axis, length, c in zip(slowest, h, clock, strict=True)
    )
    base = _sample_times(traj.duration, step, n)
    fields = sample_fields(traj, base, scalar=False)
    return MultiSegmentProfile("mstraj", *fields, True, traj, arrive, via, info)
