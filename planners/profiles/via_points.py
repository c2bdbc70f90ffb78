"""Joint trajectories through via points: multi-segment LSPB, or quintics through each point.

Two profiles plan a :class:`problems.Waypoints` problem, starting and ending at rest:

``"lspb"``
    Straight joint-space lines between the via points at constant velocity, joined by
    parabolic blends centred on each inner via point, as in Craig's "linear function with
    parabolic blends" for a path through via points (Craig, *Introduction to Robotics*, 3rd ed.,
    2005, sec. 7.3) and Corke's ``mstraj`` (*Robotics, Vision and Control*, 2nd ed., 2017,
    sec. 3.3). The path cuts the inner via points: a blend of duration tb between line
    velocities v1 and v2, centred on the via time, passes the via point at
    ``(v2 - v1) tb / 8`` per joint (the parabola's offset from its two tangents' corner). The
    first and last segments start and end at rest on the waypoints exactly: their line is the
    one through the neighbouring via point that a parabola from rest joins tangentially
    (Craig's end-segment formulas). Every joint shares each blend's timing, so the joint-space
    path is exactly the straight lines, cut only at the inner corners; positions stay within
    the range of the waypoints.

``"quintic"``
    One quintic per segment, through every via point exactly, with the via velocities of
    Craig's heuristic (sec. 7.3: the mean of the adjacent slopes when they have the same sign,
    else 0), limited so that each segment is monotone, and zero via accelerations: C2, at rest
    at both ends, and never outside the range of its waypoints (so within the position
    limits). Acceleration is zero at every via point, and the jerk jumps there.

Segment durations come from the problem (and are checked against the limits), or from the
limits. LSPB: each segment as short as its slowest joint allows at its velocity limit (like
``mstraj``), lengthened until every blend fits and every limit holds. Quintic: each segment's
rest-to-rest minimum time, rebalanced and stretched until the worst velocity or acceleration
peak, found exactly, sits on its limit.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.base import stamp
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import Waypoints
from optraj.robots import JointLimits
from optraj.validation import as_choice, as_duration

__all__ = ["PROFILES", "ViaPoints"]

FloatArray = NDArray[np.float64]

#: Profile names accepted by :class:`ViaPoints`.
PROFILES: tuple[str, ...] = ("lspb", "quintic")

#: Relative excess over a limit that is taken as round-off, not a violation; also the
#: shortest piece kept in an LSPB trajectory, as a fraction of its duration.
ROUND_OFF = 1e-12
#: Shortest automatic LSPB blend, as a fraction of the duration [-] (a blend that short only
#: absorbs a velocity change of round-off size; longer ones accelerate less).
MIN_BLEND = 1e-9
#: Extra relative lengthening per step when a segment is stretched to meet a limit, so that
#: the search ends after finitely many steps instead of creeping up to the bound.
_MARGIN = 1e-6
#: Most lengthening sweeps (LSPB, then a uniform stretch) and rebalancing rounds (quintic).
_SWEEPS = 100
_ROUNDS = 40
#: Grid of starting points [-] for Newton's search of polynomial peaks on [0, 1].
_GRID = np.linspace(0.0, 1.0, 65)


# --------------------------------------------------------------------------- shared


@dataclass(frozen=True)
class _Issue:
    """One broken limit of a candidate timing, and how to lengthen segments to mend it.

    Attributes:
        limit: ``velocity``, ``acceleration``, ``blend_time``, ``via_tolerance`` or
            ``position``.
        where: Where it happens, e.g. ``segment 2`` or ``via point 1``.
        joint: Joint index, or None.
        required: The value needed [unit].
        allowed: The limit [unit].
        unit: Unit text with a leading space, e.g. `` rad/s``.
        segments: Segments whose lengthening mends it.
        growth: Factor by which to lengthen them (may be inf when lengthening cannot help).
        fit: Whether this is a segment too short for its blends (required and allowed are
            durations [s]).
    """

    limit: str
    where: str
    joint: int | None
    required: float
    allowed: float
    unit: str
    segments: tuple[int, ...]
    growth: float
    fit: bool = False

    @property
    def ratio(self) -> float:
        """The ratio required / allowed [-]."""
        return self.required / self.allowed if self.allowed > 0.0 else math.inf

    def error(self, profile: str, names: tuple[str, ...], hint: str = "") -> InfeasibleError:
        """The InfeasibleError that reports this issue (joint, place, required and allowed)."""
        joint = None if self.joint is None else names[self.joint]
        head = f"via points ({profile}), {self.where}"
        required = f"{self.required:.6g}{self.unit}"
        allowed = f"{self.allowed:.6g}{self.unit}"
        if self.fit:
            why = f" (joint {joint!r} blending at its acceleration limit)" if joint else ""
            message = f"{head} lasts {allowed}, but its blends need {required}{why}"
        elif self.limit == "via_tolerance":
            message = (
                f"{head}: the blend passes joint {joint!r} {required} from the via point, "
                f"via_tolerance {allowed}"
            )
        else:
            message = f"{head}: needs joint {joint!r} at {required}, limit {allowed}"
        return InfeasibleError(
            message + hint,
            limit=self.limit,
            joint=joint,
            required=float(self.required),
            allowed=float(self.allowed),
        )


def _unit(limits: JointLimits, quantity: str, joint: int | None) -> str:
    """`` rad/s`` etc. for a joint, `` s`` for a duration (joint None)."""
    return " s" if joint is None else f" {limits.unit(quantity, joint)}"


def _worst_issue(issues: list[_Issue]) -> _Issue:
    """The issue with the largest required / allowed."""
    return max(issues, key=lambda issue: issue.ratio)


def _segment_phases(times: FloatArray) -> list[Phase]:
    """One phase ``segment k`` per segment between consecutive via times, k from 1 [s].

    The names are those of :class:`problems.Waypoints` and :class:`planners.OptimalControl`,
    so that a plan warm-starts another.
    """
    return [Phase(f"segment {i + 1}", times[i], times[i + 1]) for i in range(times.size - 1)]


# ----------------------------------------------------------------------------- LSPB


@dataclass
class _Layout:
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
    issues: list[_Issue] = field(default_factory=list)


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


def _lspb_layout(
    points: FloatArray,
    h: FloatArray,
    limits: JointLimits,
    blend_time: float | None,
    via_tolerance: float | None,
) -> _Layout:
    """Lines, blends and broken limits of the multi-segment LSPB with durations ``h``."""
    k, n = points.shape
    m = k - 1
    amax = limits.acceleration
    auto = blend_time is None
    d = np.diff(points, axis=0)
    dist = np.abs(d)
    times = np.concatenate([[0.0], np.cumsum(h)])
    shortest = MIN_BLEND * times[-1]  # automatic blends are no shorter (see _lspb_trajectory)
    blends = np.zeros(k)
    binding = np.full(k, -1)
    velocities = np.zeros((m, n))
    anchors = np.zeros(m)
    anchor_q = np.zeros((m, n))
    accelerations = np.zeros((k, n))
    if m == 1:
        H = float(h[0])
        if auto:
            reach = dist[0] / amax
            each = 2.0 * reach / (H + np.sqrt(np.maximum(H**2 - 4.0 * reach, 0.0)))
            binding[:] = int(np.argmax(each))
            tb = max(float(np.max(each)), shortest) if np.any(dist[0] > 0.0) else 0.0
        else:
            tb = float(blend_time)  # type: ignore[arg-type]
        blends[:] = tb
        used = min(tb, 0.5 * H)
        velocities[0] = d[0] / (H - used)
        anchors[0], anchor_q[0] = 0.5 * used, points[0]
        if used > 0.0:
            accelerations[0] = velocities[0] / used
            accelerations[1] = -accelerations[0]
    else:
        ends = ((0, 0, 1), (k - 1, m - 1, m - 1))  # (blend, segment, anchor point)
        for b, i, p in ends:
            if auto:
                blends[b], binding[b] = _end_blend(dist[i], amax, float(h[i]))
                if blends[b] > 0.0:
                    blends[b] = max(blends[b], shortest)
            else:
                blends[b] = float(blend_time)  # type: ignore[arg-type]
            used = min(blends[b], float(h[i]))
            velocities[i] = d[i] / (h[i] - 0.5 * used)
            anchors[i], anchor_q[i] = times[p], points[p]
            if used > 0.0:
                accelerations[b] = (velocities[i] if b == 0 else -velocities[i]) / used
        for i in range(1, m - 1):
            velocities[i] = d[i] / h[i]
            anchors[i], anchor_q[i] = times[i], points[i]
        change = np.diff(velocities, axis=0)  # (k - 2, n), one row per inner via point
        for c in range(1, k - 1):
            if auto:
                each = np.abs(change[c - 1]) / amax
                binding[c] = int(np.argmax(each))
                blends[c] = float(each[binding[c]])
                if blends[c] > 0.0:
                    blends[c] = max(blends[c], shortest)
            else:
                blends[c] = float(blend_time)  # type: ignore[arg-type]
            if blends[c] > 0.0:
                accelerations[c] = change[c - 1] / blends[c]
    change = np.diff(velocities, axis=0)
    deviation = change * blends[1:-1, None] / 8.0
    layout = _Layout(
        h.copy(), times, velocities, anchors, anchor_q, blends, accelerations, deviation
    )
    layout.issues = _lspb_issues(layout, limits, binding, auto, via_tolerance)
    return layout


def _lspb_issues(
    layout: _Layout,
    limits: JointLimits,
    binding: NDArray[np.intp],
    auto: bool,
    via_tolerance: float | None,
) -> list[_Issue]:
    """Every broken limit of a layout, with the lengthening that mends it."""
    vmax, amax = limits.velocity, limits.acceleration
    h, blends = layout.durations, layout.blends
    m = h.size
    k = m + 1
    issues: list[_Issue] = []
    for i in range(m):
        ratio = np.abs(layout.velocities[i]) / vmax
        j = int(np.argmax(ratio))
        if ratio[j] > 1.0 + ROUND_OFF:
            issues.append(
                _Issue(
                    "velocity",
                    f"segment {i + 1}",
                    j,
                    float(abs(layout.velocities[i, j])),
                    float(vmax[j]),
                    _unit(limits, "velocity", j),
                    (i,),
                    float(ratio[j]),
                )
            )
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
            _Issue(
                "acceleration",
                where,
                j,
                float(abs(layout.accelerations[b, j])),
                float(amax[j]),
                _unit(limits, "acceleration", j),
                segments,
                growth,
            )
        )
    for i in range(m):
        left = blends[0] if i == 0 else 0.5 * blends[i]
        right = blends[-1] if i == m - 1 else 0.5 * blends[i + 1]
        if m == 1:
            left = right = blends[0]
        need = float(left + right)
        if need > h[i] * (1.0 + ROUND_OFF):
            joint = int(binding[i] if left >= right else binding[i + 1]) if auto else None
            issues.append(
                _Issue(
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
    if via_tolerance is not None:
        for c in range(1, k - 1):
            off = np.abs(layout.deviation[c - 1])
            j = int(np.argmax(off))
            if off[j] > via_tolerance * (1.0 + ROUND_OFF):
                ratio = off[j] / via_tolerance if via_tolerance > 0.0 else math.inf
                # With automatic blends tb ~ |dv| / a, so the cut ~ dv^2 and shrinks with
                # the square of a uniform slow-down; with a fixed blend, linearly.
                issues.append(
                    _Issue(
                        "via_tolerance",
                        f"via point {c} (between segments {c - 1} and {c})",
                        j,
                        float(off[j]),
                        float(via_tolerance),
                        _unit(limits, "position", j),
                        (c - 1, c),
                        math.sqrt(ratio) if auto else ratio,
                    )
                )
    return issues


def _lspb_initial_durations(points: FloatArray, limits: JointLimits) -> FloatArray:
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


def _floor_durations(h: FloatArray) -> FloatArray:
    """Zero-length segments (repeated waypoints) get a small positive start value [s]."""
    positive = h[h > 0.0]
    floor = 1e-3 * float(np.max(positive)) if positive.size else 1.0
    return np.where(h > 0.0, h, floor)


def _lspb_fit(
    points: FloatArray,
    limits: JointLimits,
    blend_time: float | None,
    via_tolerance: float | None,
) -> _Layout:
    """The layout with durations from the limits: lengthen segments until nothing breaks."""
    h = _floor_durations(_lspb_initial_durations(points, limits))
    if blend_time is not None:
        # Each segment holds at least its blends: 1.5 tb at an end, tb inside, 2 tb alone.
        m = h.size
        shares = np.full(m, 1.0)
        shares[[0, -1]] = 1.5 if m > 1 else 2.0
        h = np.maximum(h, shares * blend_time)
    for _ in range(_SWEEPS):
        layout = _lspb_layout(points, h, limits, blend_time, via_tolerance)
        if not layout.issues:
            return layout
        growth = np.ones(h.size)
        for issue in layout.issues:
            if not math.isfinite(issue.growth):
                raise issue.error("lspb", limits.names, _LSPB_HINT)
            for i in issue.segments:
                growth[i] = max(growth[i], issue.growth * (1.0 + _MARGIN))
        h = h * growth
    # Rare: local lengthening keeps trading one broken limit for another. A uniform
    # slow-down mends every kind, so double, then bisect on the factor.
    low, high = 1.0, 2.0
    for _ in range(64):
        issues = _lspb_layout(points, high * h, limits, blend_time, via_tolerance).issues
        if not issues:
            break
        low, high = high, 2.0 * high
    else:
        raise _worst_issue(issues).error("lspb", limits.names)
    for _ in range(60):
        middle = 0.5 * (low + high)
        if _lspb_layout(points, middle * h, limits, blend_time, via_tolerance).issues:
            low = middle
        else:
            high = middle
    return _lspb_layout(points, high * h, limits, blend_time, via_tolerance)


_LSPB_HINT = (
    "; the lspb profile cuts corners by (v_out - v_in) tb / 8: profile 'quintic' passes "
    "every via point exactly"
)


def _lspb_trajectory(points: FloatArray, layout: _Layout) -> tuple[FloatArray, FloatArray]:
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


# -------------------------------------------------------------------------- quintic


#: Largest via velocity, as a multiple of an adjacent segment's slope, that keeps a quintic
#: with zero end accelerations monotone. With end velocities alpha and beta (times the slope)
#: its velocity is linear in them; on the square [0, c]^2 the worst corner is alpha = beta = c,
#: where qd(u) / slope = c - 30 (c - 1) u^2 (1 - u)^2 >= c - 30 (c - 1) / 16, which is >= 0
#: up to c = 15 / 7. (Our derivation; the same idea as Fritsch & Carlson's monotone cubics,
#: SIAM J. Numer. Anal. 17(2), 1980, whose bound is 3.)
MONOTONE_SLOPE_RATIO = 15.0 / 7.0


def _via_velocities(points: FloatArray, h: FloatArray) -> FloatArray:
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


def _quintic_segments(points: FloatArray, h: FloatArray) -> FloatArray:
    """One quintic per segment through the via points, C2, at rest at both ends.

    Each segment is the quintic Hermite interpolant of its end positions, the via velocities
    of :func:`_via_velocities` and zero accelerations (so the accelerations agree at every via
    point and the whole is C2).

    Returns:
        b, shape (m, 6, n): segment i is ``sum_p b[i, p] u^p`` with ``u = (t - s_i) / h_i``.
    """
    velocity = _via_velocities(points, h)
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


def _poly_eval(coefficients: FloatArray, u: FloatArray) -> FloatArray:
    """Polynomials (m, d + 1, n) (ascending powers) at u, shape (m, g, n) or broadcastable."""
    result = np.broadcast_to(
        coefficients[:, -1][:, None, :],
        np.broadcast_shapes((coefficients.shape[0], 1, coefficients.shape[2]), u.shape),
    ).copy()
    for i in range(coefficients.shape[1] - 2, -1, -1):
        result = result * u + coefficients[:, i][:, None, :]
    return result


def _poly_derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients of d/du, shape (m, d, n)."""
    powers = np.arange(1, coefficients.shape[1], dtype=float)[None, :, None]
    return coefficients[:, 1:] * powers


def _poly_range(coefficients: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Smallest and largest value on u in [0, 1] of each polynomial (m, d + 1, n).

    Newton's method on p' from every point of a fine grid (clipped to [0, 1]) lands on every
    stationary point; the result is the extreme value at those points and on the grid, so it
    never overstates the true range and matches it to round-off.

    Returns:
        (lowest, highest), each shape (m, n).
    """
    grid = _GRID[None, :, None]
    values = _poly_eval(coefficients, grid)
    low, high = np.min(values, axis=1), np.max(values, axis=1)
    if coefficients.shape[1] < 3:
        return low, high
    slope = _poly_derivative(coefficients)
    curve = _poly_derivative(slope)
    u = np.broadcast_to(grid, (coefficients.shape[0], grid.size, coefficients.shape[2])).copy()
    for _ in range(6):
        f1 = _poly_eval(slope, u)
        f2 = _poly_eval(curve, u)
        step = np.divide(f1, f2, out=np.zeros_like(f1), where=np.abs(f2) > 1e-300)
        u = np.clip(u - step, 0.0, 1.0)
    values = _poly_eval(coefficients, u)
    return np.minimum(low, np.min(values, axis=1)), np.maximum(high, np.max(values, axis=1))


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
    return _floor_durations(np.max(each, axis=1))


def _quintic_fit(points: FloatArray, limits: JointLimits) -> FloatArray:
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
        ratio = _quintic_ratios(_quintic_segments(points, durations), durations, limits)
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


def _quintic_issues(b: FloatArray, h: FloatArray, limits: JointLimits) -> list[_Issue]:
    """Velocity, acceleration and position limits broken by the quintics (worst per segment)."""
    speed, accel = _quintic_peaks(b, h)
    issues = []
    for quantity, values, bound in (
        ("velocity", speed, limits.velocity),
        ("acceleration", accel, limits.acceleration),
    ):
        for i in range(h.size):
            ratio = values[i] / bound
            j = int(np.argmax(ratio))
            if ratio[j] > 1.0 + ROUND_OFF:
                issues.append(
                    _Issue(
                        quantity,
                        f"segment {i + 1}",
                        j,
                        float(values[i, j]),
                        float(bound[j]),
                        _unit(limits, quantity, j),
                        (i,),
                        float(ratio[j]),
                    )
                )
    issues.extend(_position_issues(b, limits))
    return issues


def _position_issues(b: FloatArray, limits: JointLimits) -> list[_Issue]:
    """Segments whose quintic leaves the position limits (worst joint of each)."""
    lowest, highest = _poly_range(b)
    issues = []
    for i in range(b.shape[0]):
        above = highest[i] - limits.upper
        below = limits.lower - lowest[i]
        j = int(np.argmax(np.maximum(above, below)))
        if max(above[j], below[j]) > 1e-9:
            value = highest[i, j] if above[j] >= below[j] else lowest[i, j]
            bound = limits.upper[j] if above[j] >= below[j] else limits.lower[j]
            issues.append(
                _Issue(
                    "position",
                    f"segment {i + 1}",
                    j,
                    float(value),
                    float(bound),
                    _unit(limits, "position", j),
                    (i,),
                    math.inf,
                )
            )
    return issues


_QUINTIC_HINT = (
    "; every segment is built monotone, so this should not happen: please report it with the "
    "waypoints"
)


# -------------------------------------------------------------------------- planner


class ViaPoints:
    """Plan a :class:`problems.Waypoints` problem: through via points, from rest to rest.

    Args:
        profile: ``"lspb"`` (lines with parabolic blends; cuts the inner via points) or
            ``"quintic"`` (one C2 quintic per segment; passes every via point exactly).
        blend_time: For ``"lspb"``: one blend duration [s], > 0, for every blend; None for the
            shortest blend whose acceleration fits the limits at each via point.

    Raises:
        UnknownNameError: Unknown profile; lists the valid ones.
        InvalidInputError: blend_time <= 0, non-finite, or given for ``"quintic"``.
    """

    #: Name recorded in trajectory metadata.
    name = "via_points"

    def __init__(self, profile: str = "lspb", blend_time: float | None = None) -> None:
        as_choice(profile, "via-point profile", PROFILES)
        self.profile = profile
        self.blend_time: float | None = None
        if blend_time is not None:
            if profile != "lspb":
                raise InvalidInputError(
                    f"blend_time applies to profile 'lspb' only, not {profile!r}",
                    name="blend_time",
                )
            self.blend_time = as_duration(blend_time, "blend_time")

    def __repr__(self) -> str:
        blend = "" if self.blend_time is None else f", blend_time={self.blend_time!r}"
        return f"ViaPoints(profile={self.profile!r}{blend})"

    def plan(self, problem: Waypoints) -> Trajectory:
        """Plan the move through the problem's waypoints.

        Args:
            problem: The waypoints (k, n), optional segment durations (k - 1,) [s], optional
                via tolerance [rad or m], and the limits.

        Returns:
            A trajectory (degree 2 for ``"lspb"``, 5 for ``"quintic"``) from rest at the first
            waypoint to rest at the last, with phases ``segment 0`` ... ``segment k-2``
            between the via times. Metadata: ``profile``, ``segment_durations`` [s] (k - 1,),
            ``via_times`` [s] (k,), and per profile: ``blend_times`` [s] (k,),
            ``segment_velocities`` (k - 1, n), ``blend_accelerations`` (k, n),
            ``via_deviation`` (k - 2, n) [rad or m] (position minus via point at the via
            time) and ``max_via_deviation`` (lspb); ``via_velocities`` and
            ``via_accelerations`` (k, n) (quintic).

        Raises:
            InvalidInputError: Not a Waypoints problem, or every waypoint equal without
                segment durations (the move would last 0 s).
            InfeasibleError: Given segment durations break a velocity or acceleration limit
                (or the blends do not fit, or the lspb corner cut exceeds via_tolerance), or the
                quintic leaves the position limits; names the joint, the segment or
                via point, the required value and the limit.
        """
        if not isinstance(problem, Waypoints):
            raise InvalidInputError(
                f"ViaPoints plans a problems.Waypoints, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        limits = problem.limits
        if not isinstance(limits, JointLimits):  # set by Waypoints itself; kept for typing
            raise InvalidInputError("the problem has no joint limits", name="limits")
        points = np.asarray(problem.waypoints, dtype=float)
        given = problem.segment_durations
        durations = None if given is None else np.asarray(given, dtype=float)
        problem.require_motion(self.name)  # every waypoint the same, and no durations
        tolerance = problem.via_tolerance
        via_tolerance = None if tolerance is None else float(tolerance)  # type: ignore[arg-type]
        if self.profile == "lspb":
            traj = self._plan_lspb(points, durations, limits, via_tolerance)
        else:
            traj = self._plan_quintic(points, durations, limits)
        traj.metadata["durations_from"] = "limits" if durations is None else "problem"
        return stamp(traj, self.name, started, profile=self.profile)

    def _plan_lspb(
        self,
        points: FloatArray,
        durations: FloatArray | None,
        limits: JointLimits,
        via_tolerance: float | None,
    ) -> Trajectory:
        """Multi-segment LSPB trajectory."""
        if durations is None:
            layout = _lspb_fit(points, limits, self.blend_time, via_tolerance)
        else:
            layout = _lspb_layout(points, durations, limits, self.blend_time, via_tolerance)
            if layout.issues:
                worst = _worst_issue(layout.issues)
                hint = _LSPB_HINT if worst.limit == "via_tolerance" else ""
                raise worst.error("lspb", limits.names, hint)
        breakpoints, coefficients = _lspb_trajectory(points, layout)
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
            phases=_segment_phases(layout.times),
            metadata=metadata,
        )

    def _plan_quintic(
        self, points: FloatArray, durations: FloatArray | None, limits: JointLimits
    ) -> Trajectory:
        """Quintic-per-segment trajectory."""
        h = _quintic_fit(points, limits) if durations is None else durations
        b = _quintic_segments(points, h)
        issues = _quintic_issues(b, h, limits)
        if issues:
            positions = [issue for issue in issues if issue.limit == "position"]
            worst = positions[0] if positions else _worst_issue(issues)
            raise worst.error("quintic", limits.names, _QUINTIC_HINT if positions else "")
        powers = np.arange(6, dtype=float)[None, :, None]
        coefficients = b / h[:, None, None] ** powers
        times = np.concatenate([[0.0], np.cumsum(h)])
        metadata = {
            "profile": "quintic",
            "segment_durations": h,
            "via_times": times,
            "via_velocities": _via_velocities(points, h),
            "via_accelerations": np.zeros_like(points),
        }
        return Trajectory(
            times,
            coefficients,
            joint_names=limits.names,
            phases=_segment_phases(times),
            metadata=metadata,
        )
