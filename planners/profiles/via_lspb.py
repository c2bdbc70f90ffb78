"""Multi-segment LSPB through via points: straight joint-space lines joined by parabolic blends.

Straight lines between the via points at constant velocity, joined by parabolic blends centred
on each inner via point, as in Craig's "linear function with parabolic blends" for a path
through via points (Craig, *Introduction to Robotics*, 3rd ed., 2005, sec. 7.3) and Corke's
``mstraj`` (*Robotics, Vision and Control*, 2nd ed., 2017, sec. 3.3). The path cuts the inner
via points: a blend of duration tb between line velocities v1 and v2, centred on the via time,
passes the via point at ``(v2 - v1) tb / 8`` per joint (the parabola's offset from its two
tangents' corner). The first and last segments start and end at rest on the waypoints
exactly: their line is the one through the neighbouring via point that a parabola from rest
joins tangentially (Craig's end-segment formulas). Every joint shares each blend's timing, so
the joint-space path is exactly the straight lines, cut only at the inner corners.

:func:`lspb_layout` lays out the lines and blends for given segment durations and lists the
limits they break; :func:`lspb_fit` finds durations from the limits (each segment as short as
its slowest joint allows at its velocity limit, like ``mstraj``, lengthened until every blend
fits and every limit holds); :func:`plan_lspb` makes the trajectory. Plan through
:class:`optraj.planners.ViaPoints` with profile ``"lspb"``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

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

__all__ = ["LSPB_HINT", "MIN_BLEND", "LSPBLayout", "lspb_fit", "lspb_layout", "plan_lspb"]

FloatArray = NDArray[np.float64]

#: Shortest automatic LSPB blend, as a fraction of the duration [-] (a blend that short only
#: absorbs a velocity change of round-off size; longer ones accelerate less).
MIN_BLEND = 1e-9
#: Extra relative lengthening per step when a segment is stretched to meet a limit, so that
#: the search ends after finitely many steps instead of creeping up to the bound.
_MARGIN = 1e-6
#: Most lengthening sweeps before a uniform stretch.
_SWEEPS = 100

#: Appended to the error of a corner cut beyond the via tolerance.
LSPB_HINT = (
    "; the lspb profile cuts corners by (v_out - v_in) tb / 8: profile 'quintic' passes "
    "every via point exactly"
)


@dataclass
class LSPBLayout:
    """Lines and blends of a multi-segment LSPB for given segment durations.

    Attributes:
        durations: Segment durations h [s], shape (m,).
        times: Via times s [s], shape (k,) = (m + 1,): s_0 = 0, s_i = h_0 + ... + h_{i-1}.
        velocities: Line velocity of each segment [rad/s or m/s], shape (m, n).
        anchors: Time [s] at which each line passes its anchor position, shape (m,).
        anchor_q: Anchor positions [rad or m], shape (m, n).
        blends: Blend durations [s], shape (k,): the start blend, one per inner via point,
            the end blend (for one segment: its two blends).
        accelerations: Blend accelerations [rad/s^2 or m/s^2], shape (k, n).
        deviation: Position minus via point at each inner via time [rad or m], shape
            (k - 2, n): (v_out - v_in) tb / 8.
        issues: Broken limits; the layout is a trajectory only when empty.
    """

    durations: FloatArray
    times: FloatArray
    velocities: FloatArray
    anchors: FloatArray
    anchor_q: FloatArray
    blends: FloatArray
    accelerations: FloatArray
    deviation: FloatArray
    issues: list[TimingIssue] = field(default_factory=list)


# ------------------------------------------------------------------------- layout


def _end_blend(dist: FloatArray, amax: FloatArray, h: float) -> tuple[float, int]:
    """Shortest shared blend from rest into a line through the far via point, and its joint.

    With ``v = d / (h - t/2)`` and ``a = v / t`` (Craig 2005, sec. 7.3, first segment),
    ``a <= a_max`` needs ``t (h - t/2) >= |d| / a_max``: ``t >= h - sqrt(h^2 - 2 |d| / a_max)``,
    written without cancellation. A discriminant below zero (h too short) is clipped; the
    acceleration check then reports it.
    """
    reach = dist / amax
    each = 2.0 * reach / (h + np.sqrt(np.maximum(h**2 - 2.0 * reach, 0.0)))
    j = int(np.argmax(each))
    return float(each[j]), j


class _BlendRule(NamedTuple):
    """How the blends of a layout are chosen.

    Attributes:
        amax: Acceleration limits [rad/s^2 or m/s^2], shape (n,).
        blend_time: One blend duration [s] for all, or None: each blend the shortest whose
            acceleration fits ``amax``, and no shorter than ``shortest`` [s].
        shortest: Shortest automatic blend [s].
        binding: Filled in: the joint at its acceleration limit in each automatic blend,
            shape (k,) (-1 where none).
    """

    amax: FloatArray
    blend_time: float | None
    shortest: float
    binding: NDArray[np.intp]


def _lay_one_segment(layout: LSPBLayout, points: FloatArray, rule: _BlendRule) -> None:
    """Fill in ``layout`` for two waypoints: one synchronised rest-to-rest move."""
    amax, blend_time, shortest, binding = rule
    d = points[1] - points[0]
    dist = np.abs(d)
    H = float(layout.durations[0])
    if blend_time is None:
        reach = dist / amax
        each = 2.0 * reach / (H + np.sqrt(np.maximum(H**2 - 4.0 * reach, 0.0)))
        binding[:] = int(np.argmax(each))
        tb = max(float(np.max(each)), shortest) if np.any(dist > 0.0) else 0.0
    else:
        tb = blend_time
    layout.blends[:] = tb
    used = min(tb, 0.5 * H)
    layout.velocities[0] = d / (H - used)
    layout.anchors[0], layout.anchor_q[0] = 0.5 * used, points[0]
    if used > 0.0:
        layout.accelerations[0] = layout.velocities[0] / used
        layout.accelerations[1] = -layout.accelerations[0]


def _lay_end_segments(layout: LSPBLayout, points: FloatArray, rule: _BlendRule) -> None:
    """Fill in the first and last segments of ``layout`` (three waypoints or more).

    Each starts or ends at rest with a blend on its waypoint, its line through the
    neighbouring via point; the inner segments' lines pass their via points.
    """
    amax, blend_time, shortest, binding = rule
    k = points.shape[0]
    m = k - 1
    h, times = layout.durations, layout.times
    d = np.diff(points, axis=0)
    for b, i, p in ((0, 0, 1), (k - 1, m - 1, m - 1)):  # (blend, segment, anchor point)
        if blend_time is None:
            layout.blends[b], binding[b] = _end_blend(np.abs(d[i]), amax, float(h[i]))
            if layout.blends[b] > 0.0:
                layout.blends[b] = max(layout.blends[b], shortest)
        else:
            layout.blends[b] = blend_time
        used = min(layout.blends[b], float(h[i]))
        layout.velocities[i] = d[i] / (h[i] - 0.5 * used)
        layout.anchors[i], layout.anchor_q[i] = times[p], points[p]
        if used > 0.0:
            velocity = layout.velocities[i]
            layout.accelerations[b] = (velocity if b == 0 else -velocity) / used
    for i in range(1, m - 1):
        layout.velocities[i] = d[i] / h[i]
        layout.anchors[i], layout.anchor_q[i] = times[i], points[i]


def _lay_inner_blends(layout: LSPBLayout, rule: _BlendRule) -> None:
    """Fill in the blends at the inner via points of ``layout``, between its lines."""
    amax, blend_time, shortest, binding = rule
    change = np.diff(layout.velocities, axis=0)  # (k - 2, n), one row per inner via point
    for c in range(1, layout.blends.size - 1):
        if blend_time is None:
            each = np.abs(change[c - 1]) / amax
            binding[c] = int(np.argmax(each))
            layout.blends[c] = float(each[binding[c]])
            if layout.blends[c] > 0.0:
                layout.blends[c] = max(layout.blends[c], shortest)
        else:
            layout.blends[c] = blend_time
        if layout.blends[c] > 0.0:
            layout.accelerations[c] = change[c - 1] / layout.blends[c]


def lspb_layout(
    points: FloatArray,
    h: FloatArray,
    limits: JointLimits,
    blend_time: float | None,
    via_tolerance: float | None,
) -> LSPBLayout:
    """Lines, blends and broken limits of the multi-segment LSPB with durations ``h``.

    Args:
        points: Waypoints [rad or m], shape (k, n), k >= 2.
        h: Segment durations [s], shape (k - 1,), > 0.
        limits: The joint limits.
        blend_time: One blend duration [s] for every blend, or None for the shortest blend
            at each via point whose acceleration fits the limits.
        via_tolerance: Largest corner cut [rad or m] at an inner via point, or None.

    Returns:
        The layout; its ``issues`` list what it breaks (empty when it is a valid plan).
    """
    k, n = points.shape
    m = k - 1
    times = np.concatenate([[0.0], np.cumsum(h)])
    shortest = MIN_BLEND * times[-1]  # automatic blends are no shorter (see _pieces)
    layout = LSPBLayout(
        h.copy(),
        times,
        np.zeros((m, n)),
        np.zeros(m),
        np.zeros((m, n)),
        np.zeros(k),
        np.zeros((k, n)),
        np.zeros((k - 2, n)),
    )
    binding = np.full(k, -1)
    rule = _BlendRule(limits.acceleration, blend_time, shortest, binding)
    if m == 1:
        _lay_one_segment(layout, points, rule)
    else:
        _lay_end_segments(layout, points, rule)
        _lay_inner_blends(layout, rule)
    change = np.diff(layout.velocities, axis=0)
    layout.deviation = change * layout.blends[1:-1, None] / 8.0
    auto = blend_time is None
    layout.issues = [
        *segment_issues("velocity", np.abs(layout.velocities), limits.velocity, limits),
        *_acceleration_issues(layout, limits, auto),
        *_fit_issues(layout, binding, auto),
        *_tolerance_issues(layout, limits, auto, via_tolerance),
    ]
    return layout


# ------------------------------------------------------------------------- issues


def _acceleration_issues(layout: LSPBLayout, limits: JointLimits, auto: bool) -> list[TimingIssue]:
    """Blends whose acceleration breaks a limit (worst joint of each)."""
    amax = limits.acceleration
    k = layout.blends.size
    m = k - 1
    issues = []
    for b in range(k):
        ratio = np.abs(layout.accelerations[b]) / amax
        j = int(np.argmax(ratio))
        if ratio[j] <= 1.0 + ROUND_OFF:
            continue
        if b in (0, k - 1):
            segments: tuple[int, ...] = (0,) if b == 0 else (m - 1,)
            where = f"segment {segments[0] + 1} ({'start' if b == 0 else 'end'} blend)"
            # An automatic end blend breaks the limit only when the segment is too short
            # for any blend: a = 2 |d| / h^2 there, so h grows with the square root.
            growth = math.sqrt(ratio[j]) if auto else float(ratio[j])
        else:
            segments, where = (b - 1, b), f"via point {b} (between segments {b - 1} and {b})"
            growth = float(ratio[j])
        issues.append(
            TimingIssue(
                "acceleration",
                where,
                j,
                float(abs(layout.accelerations[b, j])),
                float(amax[j]),
                limit_unit(limits, "acceleration", j),
                segments,
                growth,
            )
        )
    return issues


def _fit_issues(layout: LSPBLayout, binding: NDArray[np.intp], auto: bool) -> list[TimingIssue]:
    """Segments too short to hold their blends (half of an inner blend, all of an end one)."""
    h, blends = layout.durations, layout.blends
    m = h.size
    issues = []
    for i in range(m):
        left = blends[0] if i == 0 else 0.5 * blends[i]
        right = blends[-1] if i == m - 1 else 0.5 * blends[i + 1]
        if m == 1:
            left = right = blends[0]
        need = float(left + right)
        if need > h[i] * (1.0 + ROUND_OFF):
            joint = int(binding[i] if left >= right else binding[i + 1]) if auto else None
            issues.append(
                TimingIssue(
                    "acceleration" if auto else "blend_time",
                    f"segment {i + 1}",
                    joint if joint is not None and joint >= 0 else None,
                    need,
                    float(h[i]),
                    " s",
                    (i,),
                    need / float(h[i]),
                    fit=True,
                )
            )
    return issues


def _tolerance_issues(
    layout: LSPBLayout, limits: JointLimits, auto: bool, via_tolerance: float | None
) -> list[TimingIssue]:
    """Inner via points that a blend passes farther than ``via_tolerance`` (worst joint)."""
    if via_tolerance is None:
        return []
    issues = []
    for c in range(1, layout.blends.size - 1):
        off = np.abs(layout.deviation[c - 1])
        j = int(np.argmax(off))
        if off[j] > via_tolerance * (1.0 + ROUND_OFF):
            ratio = off[j] / via_tolerance if via_tolerance > 0.0 else math.inf
            # With automatic blends tb ~ |dv| / a, so the cut ~ dv^2 and shrinks with
            # the square of a uniform slow-down; with a fixed blend, linearly.
            issues.append(
                TimingIssue(
                    "via_tolerance",
                    f"via point {c} (between segments {c - 1} and {c})",
                    j,
                    float(off[j]),
                    float(via_tolerance),
                    limit_unit(limits, "position", j),
                    (c - 1, c),
                    math.sqrt(ratio) if auto else ratio,
                )
            )
    return issues


# ---------------------------------------------------------------------------- fit


def _initial_durations(points: FloatArray, limits: JointLimits) -> FloatArray:
    """Each segment as short as its slowest joint allows (the ends also accelerate from rest).

    Inner segments: ``max_j |d_j| / v_max_j`` (``mstraj``'s qdmax rule). A first or last
    segment whose joint reaches v_max needs ``|d| / v_max + v_max / (2 a_max)``, else
    ``sqrt(2 |d| / a_max)``; a single segment needs the LSPB minimum time.
    """
    vmax, amax = limits.velocity, limits.acceleration
    dist = np.abs(np.diff(points, axis=0))
    h = np.max(dist / vmax, axis=1)
    m = h.size
    if m == 1:
        cruise = dist[0] >= vmax**2 / amax
        each = np.where(cruise, dist[0] / vmax + vmax / amax, 2.0 * np.sqrt(dist[0] / amax))
        return np.array([float(np.max(each))])
    for i in (0, m - 1):
        cruise = dist[i] >= vmax**2 / (2.0 * amax)
        each = np.where(cruise, dist[i] / vmax + vmax / (2.0 * amax), np.sqrt(2.0 * dist[i] / amax))
        h[i] = float(np.max(each))
    return h


def _growth(issues: list[TimingIssue], m: int, names: tuple[str, ...]) -> FloatArray:
    """Factor per segment [-] that mends every issue on its own, with a small margin.

    Raises:
        InfeasibleError: An issue no lengthening mends (a corner cut at zero tolerance).
    """
    growth = np.ones(m)
    for issue in issues:
        if not math.isfinite(issue.growth):
            raise issue.error("lspb", names, LSPB_HINT)
        for i in issue.segments:
            growth[i] = max(growth[i], issue.growth * (1.0 + _MARGIN))
    return growth


def _stretch(
    layout_of: Callable[[FloatArray], LSPBLayout], h: FloatArray, names: tuple[str, ...]
) -> LSPBLayout:
    """The shortest valid layout of durations c h, c >= 1: doubling, then bisection on c.

    A uniform slow-down mends every kind of issue, where local lengthening may keep trading
    one broken limit for another.
    """
    low, high = 1.0, 2.0
    for _ in range(64):
        issues = layout_of(high * h).issues
        if not issues:
            break
        low, high = high, 2.0 * high
    else:
        raise worst_issue(issues).error("lspb", names)
    for _ in range(60):
        middle = 0.5 * (low + high)
        if layout_of(middle * h).issues:
            low = middle
        else:
            high = middle
    return layout_of(high * h)


def lspb_fit(
    points: FloatArray,
    limits: JointLimits,
    blend_time: float | None,
    via_tolerance: float | None,
) -> LSPBLayout:
    """The layout with durations from the limits: lengthen segments until nothing breaks.

    Args:
        points: Waypoints [rad or m], shape (k, n), not all equal.
        limits: The joint limits.
        blend_time: As for :func:`lspb_layout`.
        via_tolerance: As for :func:`lspb_layout`.

    Returns:
        A layout without issues.

    Raises:
        InfeasibleError: No lengthening mends an issue (a corner cut at zero tolerance).
    """
    h = floor_durations(_initial_durations(points, limits))
    if blend_time is not None:
        # Each segment holds at least its blends: 1.5 tb at an end, tb inside, 2 tb alone.
        m = h.size
        shares = np.full(m, 1.0)
        shares[[0, -1]] = 1.5 if m > 1 else 2.0
        h = np.maximum(h, shares * blend_time)

    def layout_of(durations: FloatArray) -> LSPBLayout:
        return lspb_layout(points, durations, limits, blend_time, via_tolerance)

    for _ in range(_SWEEPS):
        layout = layout_of(h)
        if not layout.issues:
            return layout
        h = h * _growth(layout.issues, h.size, limits.names)
    # Rare: local lengthening keeps trading one broken limit for another.
    return _stretch(layout_of, h, limits.names)


# --------------------------------------------------------------------- trajectory


def _pieces(points: FloatArray, layout: LSPBLayout) -> tuple[FloatArray, FloatArray]:
    """Breakpoints (K + 1,) and degree-2 coefficients (K, 3, n) of a valid layout."""
    k, n = points.shape
    m = k - 1
    times, blends = layout.times, layout.blends
    v, acc = layout.velocities, layout.accelerations
    T = float(times[-1])
    zero = np.zeros(n)
    # Pieces (start, end, reference time, position and velocity there, acceleration): each
    # is exact in absolute time, and re-expanded about its breakpoint below.
    pieces: list[tuple[float, float, float, FloatArray, FloatArray, FloatArray]] = []
    first = blends[0]
    last = T - blends[-1]
    pieces.append((0.0, first, 0.0, points[0], zero, acc[0]))
    for i in range(m):
        start = first if i == 0 else times[i] + 0.5 * blends[i]
        end = last if i == m - 1 else times[i + 1] - 0.5 * blends[i + 1]
        pieces.append((start, end, layout.anchors[i], layout.anchor_q[i], v[i], zero))
        if i < m - 1:
            c = i + 1
            t0 = times[c] - 0.5 * blends[c]
            q0 = layout.anchor_q[i] + v[i] * (t0 - layout.anchors[i])
            pieces.append((t0, times[c] + 0.5 * blends[c], t0, q0, v[i], acc[c]))
    pieces.append((last, T, T, points[-1], zero, acc[-1]))
    # Pieces shorter than round-off (1e-12 T) are dropped, so that breakpoints survive
    # shifting (Trajectory.then). Only lines can be that short (automatic blends last at
    # least MIN_BLEND T): their neighbours then meet with a velocity mismatch of round-off.
    gap = ROUND_OFF * T
    kept: list[tuple[float, float, FloatArray, FloatArray, FloatArray]] = []
    for start, end, ref, q, qd, qdd in pieces:
        if end - start <= gap or T - start <= gap:
            continue  # empty (no blend needed, or a line fully covered by its blends)
        while kept and start - kept[-1][0] <= gap:
            kept.pop()  # a round-off sliver
        kept.append((max(start, 0.0), ref, q, qd, qdd))
    breakpoints = np.array([piece[0] for piece in kept] + [T])
    coefficients = np.empty((len(kept), 3, n))
    for row, (start, ref, q, qd, qdd) in enumerate(kept):
        shift = start - ref
        coefficients[row, 0] = q + qd * shift + 0.5 * qdd * shift**2
        coefficients[row, 1] = qd + qdd * shift
        coefficients[row, 2] = 0.5 * qdd
    coefficients[0, 0] = points[0]  # exact start (the first piece starts there anyway)
    return breakpoints, coefficients


def plan_lspb(
    points: FloatArray,
    durations: FloatArray | None,
    limits: JointLimits,
    blend_time: float | None,
    via_tolerance: float | None,
) -> Trajectory:
    """Multi-segment LSPB trajectory through the waypoints, from rest to rest.

    Args:
        points: Waypoints [rad or m], shape (k, n), k >= 2.
        durations: Segment durations [s], shape (k - 1,), or None to find them from the limits.
        limits: The joint limits.
        blend_time: As for :func:`lspb_layout`.
        via_tolerance: As for :func:`lspb_layout`.

    Returns:
        A degree-2 trajectory with phases ``segment 1`` ... ``segment k-1``; metadata
        ``profile``, ``segment_durations``, ``via_times``, ``blend_times``,
        ``segment_velocities``, ``blend_accelerations``, ``via_deviation`` and
        ``max_via_deviation``.

    Raises:
        InfeasibleError: Given durations break a limit (or the blends do not fit, or a
            corner cut exceeds via_tolerance), or no lengthening mends a corner cut.
    """
    if durations is None:
        layout = lspb_fit(points, limits, blend_time, via_tolerance)
    else:
        layout = lspb_layout(points, durations, limits, blend_time, via_tolerance)
        if layout.issues:
            worst = worst_issue(layout.issues)
            hint = LSPB_HINT if worst.limit == "via_tolerance" else ""
            raise worst.error("lspb", limits.names, hint)
    breakpoints, coefficients = _pieces(points, layout)
    deviation = layout.deviation
    metadata = {
        "profile": "lspb",
        "segment_durations": layout.durations,
        "via_times": layout.times,
        "blend_times": layout.blends,
        "segment_velocities": layout.velocities,
        "blend_accelerations": layout.accelerations,
        "via_deviation": deviation,
        "max_via_deviation": float(np.max(np.abs(deviation))) if deviation.size else 0.0,
    }
    return Trajectory(
        breakpoints,
        coefficients,
        joint_names=limits.names,
        phases=segment_phases(layout.times),
        metadata=metadata,
    )
