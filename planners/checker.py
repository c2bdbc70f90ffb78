"""The independent trajectory checker: every limit and every task constraint, densely sampled.

:func:`check` judges any :class:`~planners.trajectory.Trajectory` against a robot's joint limits
and, for a problem, against the task constraints it lists (``problem.constraints()``). It trusts
nothing a planner says: it reads only the trajectory's breakpoints, polynomial coefficients and
phases (the planner name is copied into the summary, nothing else of the metadata is used).

How the worst values are found:

* Joint quantities (position, velocity, acceleration, jerk) are bounded exactly on every
  polynomial segment, whatever the sampling rate: the worst value is taken over each segment's
  ends and the real roots of the next derivative, for every segment whose Bernstein enclosure
  could beat the best end or break the limit, vectorised over segments and joints.
* Torques are computed by inverse dynamics (Pinocchio's RNEA, through :class:`robots.Robot`) at
  every sample: ``rate`` plus every breakpoint and the instant just before each.
* Jumps are measured exactly, from the polynomial on each side of every breakpoint, and between
  a prescribed start or end velocity (and acceleration, when prescribed) and the trajectory's.
  A jump in a quantity makes every higher derivative unbounded: such findings fail with value
  ``inf``.
* Every comparison (a limit, a jump, a boundary state) allows the same round-off,
  :func:`round_off`: a relative ``RELATIVE_SLACK`` of the value's scale plus what the value
  changes over the round-off of the time at which it is computed.
* Task constraints (tool on a line, strike schedule, contact) are measured from the tool frame
  pose and Jacobian, computed in one batched call over every instant needed.

Example::

    report = check(trajectory, problem)
    print(report)  # a table of every finding
    assert report.ok, report.violations
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.trajectory import MAX_RATE, TIME_TOLERANCE, Phase, Trajectory, sampling_rate
from optraj.problems.constraints import (
    BoundaryState,
    Constraint,
    StrikeLine,
    ToolContact,
    ToolPath,
    ViaPoint,
)
from optraj.robots import JointLimits, Robot
from optraj.validation import as_choice, as_flag, as_number, as_positive, as_vector

__all__ = [
    "ABSOLUTE_SLACK",
    "MAX_RATE",
    "QUANTITIES",
    "RELATIVE_SLACK",
    "STRIKE_WINDOW_TOLERANCE",
    "TIME_ROUND_OFF",
    "Checkable",
    "Finding",
    "Report",
    "TrajectoryInfo",
    "check",
    "round_off",
    "state_allowance",
]

FloatArray = NDArray[np.float64]

#: The limited joint quantities, in report order.
QUANTITIES: tuple[str, ...] = ("position", "velocity", "acceleration", "jerk", "torque")
#: Allowed difference between a strike phase's length and the commanded window [s].
STRIKE_WINDOW_TOLERANCE = 1e-6

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
#: Relative size below which a leading polynomial coefficient is treated as zero when its
#: roots are sought (a few machine epsilons: dropping it moves the polynomial by less than
#: that fraction of its largest coefficient on the segment).
_NEGLIGIBLE = 64.0 * float(np.finfo(float).eps)
#: Most segments whose via-point distance is examined exactly (the closest samples' segments).
_MAX_REFINED = 64


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


#: Derivative order of each joint quantity (torque depends on the acceleration).
_ORDER = {"position": 0, "velocity": 1, "acceleration": 2, "jerk": 3, "torque": 2}
#: JointLimits field and unit key of each symmetric quantity.
_LIMIT_FIELD = {
    "velocity": "velocity",
    "acceleration": "acceleration",
    "jerk": "jerk",
    "torque": "effort",
}
_UNIT_KEY = {**{q: q for q in QUANTITIES}, "torque": "effort"}
_ORDER_NAME = ("position", "velocity", "acceleration")
_STATE_NAME = ("q", "qd", "qdd")


# ------------------------------------------------------------------------------ results


class Checkable(Protocol):
    """What :func:`check` accepts besides a robot: any problem with these three members."""

    @property
    def robot(self) -> Robot:
        """The robot that is to move."""
        ...

    @property
    def limits(self) -> JointLimits:
        """The joint limits to judge against."""
        ...

    def constraints(self) -> tuple[Constraint, ...]:
        """The task constraints to judge against."""
        ...


@dataclass(frozen=True)
class Finding:
    """One measured limit or constraint: its worst value, where it happens, and the verdict.

    Attributes:
        name: What was measured, e.g. ``"velocity"`` or ``"strike speed"``.
        kind: ``"limit"`` for a joint limit, ``"task"`` for a problem constraint.
        value: The worst value, in ``unit``: the position nearest (or beyond) its bounds, the
            largest magnitude of a symmetric quantity, or the largest constraint deviation;
            ``inf`` when a jump makes the quantity unbounded.
        limit: The bound it is compared with (the nearer position bound, the limit, or the
            constraint's tolerance), in ``unit``.
        margin: How far inside the bound the worst value stays (negative when outside), in
            ``unit``; ``-inf`` for an unbounded quantity.
        ratio: ``value / limit`` [-] (``inf`` allowed); for positions, the distance from the
            middle of the range over half the range (1 on a bound).
        time: When the worst value happens [s], or None.
        joint: The joint concerned, or None.
        unit: Unit of value, limit and margin, e.g. ``"rad/s"`` (``"-"`` for a relative error).
        detail: One readable sentence on the worst case.
        ok: Whether the finding passes: margin >= -slack, the slack from :func:`round_off`
            (a relative 1e-9 of the scale, 1e-12, and the time round-off times the slope).
    """

    name: str
    kind: Literal["limit", "task"]
    value: float
    limit: float
    margin: float
    ratio: float
    time: float | None
    joint: str | None
    unit: str
    detail: str
    ok: bool

    def __post_init__(self) -> None:
        if self.kind not in ("limit", "task"):
            raise InvalidInputError(
                f"finding kind must be 'limit' or 'task', got {self.kind!r}", name="kind"
            )
        for name in ("value", "limit", "margin", "ratio", "time"):
            raw = getattr(self, name)
            if raw is None and name == "time":
                continue
            if isinstance(raw, bool) or not isinstance(raw, (int, float, np.integer, np.floating)):
                raise InvalidInputError(
                    f"finding {self.name!r}: {name} must be a number, got {raw!r}", name=name
                )
            number = float(raw)
            if math.isnan(number):
                raise InvalidInputError(f"finding {self.name!r}: {name} is NaN", name=name)
            object.__setattr__(self, name, number)
        object.__setattr__(self, "ok", as_flag(self.ok, "ok"))


@dataclass(frozen=True)
class TrajectoryInfo:
    """What was checked.

    Attributes:
        duration: Trajectory duration [s].
        dof: Number of joints.
        segments: Number of polynomial segments.
        samples: Number of sampled instants.
        rate: Sampling rate [Hz].
        planner: The planner name from the trajectory's metadata, or None (not trusted
            otherwise).
        robot: Robot name.
    """

    duration: float
    dof: int
    segments: int
    samples: int
    rate: float
    planner: str | None
    robot: str


@dataclass(frozen=True)
class Report:
    """Every finding of one check.

    Attributes:
        findings: The limit findings (in :data:`QUANTITIES` order) then the task findings.
        trajectory: Summary of the checked trajectory.
    """

    findings: tuple[Finding, ...]
    trajectory: TrajectoryInfo

    @property
    def ok(self) -> bool:
        """Whether every finding passes."""
        return all(finding.ok for finding in self.findings)

    @property
    def violations(self) -> tuple[Finding, ...]:
        """The failing findings."""
        return tuple(finding for finding in self.findings if not finding.ok)

    @property
    def names(self) -> tuple[str, ...]:
        """Names of all findings, in order."""
        return tuple(finding.name for finding in self.findings)

    def __getitem__(self, name: str) -> Finding:
        """The finding called ``name``.

        Raises:
            UnknownNameError: No such finding; lists the findings.
        """
        for finding in self.findings:
            if finding.name == name:
                return finding
        raise UnknownNameError("finding", name, self.names)

    def passed(self, *names: str) -> bool:
        """Whether the named findings (all findings when none are named) pass.

        Raises:
            UnknownNameError: A name is not a finding of this report.
        """
        if not names:
            return self.ok
        return all(self[name].ok for name in names)

    def summary(self) -> str:
        """A fixed-width table of every finding, headed by the trajectory and the verdict."""
        info = self.trajectory
        planner = "?" if info.planner is None else repr(info.planner)
        head = (
            f"check of a {info.duration:.6g} s trajectory: robot {info.robot!r}, {info.dof} "
            f"joints, {info.segments} segments, planner {planner}, {info.samples} samples "
            f"at {info.rate:.6g} Hz"
        )
        bad = self.violations
        listed = ", ".join(f.name for f in bad[:6]) + (", ..." if len(bad) > 6 else "")
        verdict = (
            f"PASS: all {len(self.findings)} findings pass"
            if not bad
            else f"FAIL: {len(bad)} of {len(self.findings)} findings fail ({listed})"
        )
        width = max([len("name"), *(len(f.name) for f in self.findings)])
        joint_width = max([len("joint"), *(len(f.joint or "-") for f in self.findings)])
        unit_width = max([len("unit"), *(len(f.unit) for f in self.findings)])
        columns = (
            f"{'name':<{width}}  {'ok':<4}  {'value':>11}  {'limit':>11}  {'margin':>11}  "
            f"{'ratio':>9}  {'time [s]':>9}  {'joint':<{joint_width}}  "
            f"{'unit':<{unit_width}}  detail"
        )
        lines = [head, verdict, columns, "-" * len(columns)]
        for f in self.findings:
            time = "-" if f.time is None else f"{f.time:.4f}"
            lines.append(
                f"{f.name:<{width}}  {'ok' if f.ok else 'FAIL':<4}  {_number(f.value):>11}  "
                f"{_number(f.limit):>11}  {_number(f.margin):>11}  {_number(f.ratio, 3):>9}  "
                f"{time:>9}  {f.joint or '-':<{joint_width}}  {f.unit:<{unit_width}}  "
                f"{f.detail}"
            )
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def _number(value: float, digits: int = 4) -> str:
    """A number for the summary table: ``inf`` / ``-inf`` spelled out, else ``digits`` figures."""
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return f"{value:.{digits}g}"


def _finding(
    name: str,
    kind: Literal["limit", "task"],
    value: float,
    limit: float,
    *,
    time: float | None,
    joint: str | None,
    unit: str,
    detail: str,
    margin: float | None = None,
    ratio: float | None = None,
    slack: float | None = None,
) -> Finding:
    """Build a finding: margin, ratio and verdict from value and limit, NaN turned into a fail.

    Args:
        name: Finding name.
        kind: ``"limit"`` or ``"task"``.
        value: Worst value [unit].
        limit: Bound or tolerance [unit].
        time: When [s], or None.
        joint: Which joint, or None.
        unit: Unit text.
        detail: Explanation.
        margin: ``limit - value`` when None [unit].
        ratio: ``value / limit`` when None [-].
        slack: The pass slack [unit] (see :func:`round_off`); the round-off of ``limit`` when
            None.
    """
    value = float(value)
    limit = float(limit)
    if math.isnan(value):
        value, detail = math.inf, f"{detail} (the value is not a number)"
    margin = limit - value if margin is None else float(margin)
    if math.isnan(margin) or math.isinf(value):
        margin = -math.inf
    if ratio is None:
        ratio = value / limit if limit != 0.0 else (0.0 if value == 0.0 else math.inf)
    if math.isnan(ratio):
        ratio = math.inf
    if slack is None:
        slack = float(round_off(limit))
    return Finding(
        name=name,
        kind=kind,
        value=value,
        limit=limit,
        margin=margin,
        ratio=ratio,
        time=None if time is None else float(time),
        joint=joint,
        unit=unit,
        detail=detail,
        ok=margin >= -slack,
    )


# ---------------------------------------------------------------------- polynomial helpers


def _derivatives(coefficients: FloatArray, count: int) -> list[FloatArray]:
    """Coefficients of the position polynomial and its first ``count`` time derivatives.

    Args:
        coefficients: Shape (K, d + 1, n), ascending powers of the local time.
        count: Number of derivatives.

    Returns:
        ``count + 1`` arrays, the r-th of shape (K, max(d + 1 - r, 1), n).
    """
    result = [np.asarray(coefficients, dtype=float)]
    for _ in range(count):
        last = result[-1]
        if last.shape[1] == 1:
            result.append(np.zeros_like(last))
        else:
            powers = np.arange(1, last.shape[1], dtype=float)[None, :, None]
            result.append(last[:, 1:, :] * powers)
    return result


def _segments(knots: FloatArray, times: FloatArray) -> NDArray[np.intp]:
    """Segment index of each time (right-continuous, the last segment at the end time)."""
    index = np.searchsorted(knots, times, side="right") - 1
    return np.clip(index, 0, len(knots) - 2)


def _evaluate(coefficients: FloatArray, knots: FloatArray, times: FloatArray) -> FloatArray:
    """Piecewise polynomial values at the given times, shape (m, n)."""
    segment = _segments(knots, times)
    tau = (times - knots[segment])[:, None]
    rows = coefficients[segment]
    result = rows[:, -1, :].copy()
    for i in range(rows.shape[1] - 2, -1, -1):
        result = result * tau + rows[:, i, :]
    return result


def _polyval(coefficients: FloatArray, tau: FloatArray) -> FloatArray:
    """One polynomial (ascending coefficients) at local times ``tau``."""
    result = np.full(np.shape(tau), coefficients[-1], dtype=float)
    for c in coefficients[-2::-1]:
        result = result * tau + c
    return result


def _critical_points(coefficients: FloatArray, length: float) -> FloatArray:
    """Local times in [0, length] where a polynomial may take its extremes.

    The two ends and the (nearly) real roots of its derivative; extra candidates only cost an
    evaluation, so nearly real roots (double roots come out slightly complex) are kept.
    """
    candidates = [np.array([0.0, length])]
    if coefficients.size > 1:
        slope = coefficients[1:] * np.arange(1, coefficients.size)
        candidates.append(_real_roots(slope, length))
    return np.concatenate(candidates)


def _real_roots(coefficients: FloatArray, length: float) -> FloatArray:
    """Nearly real roots of a polynomial (ascending coefficients) within [0, length]."""
    if not np.any(coefficients):
        return np.empty(0)
    roots = np.roots(coefficients[::-1])
    near = roots[np.abs(roots.imag) <= 1e-6 * (length + np.abs(roots.real))].real
    return np.clip(near[(near > -1e-9 * length) & (near < length * (1 + 1e-9))], 0.0, length)


def _horner(coefficients: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Value and derivative of each row's polynomial at its points, by Horner's scheme.

    Args:
        coefficients: Ascending powers, one polynomial per row, shape (R, d + 1).
        u: Points, shape (R, c).

    Returns:
        (value, derivative), each shape (R, c).
    """
    value = np.zeros_like(u)
    derivative = np.zeros_like(u)
    for i in range(coefficients.shape[1] - 1, -1, -1):
        derivative = derivative * u + value
        value = value * u + coefficients[:, i : i + 1]
    return value, derivative


def _unit_roots(slope: FloatArray) -> FloatArray:
    """Real parts of the roots of many polynomials, clipped onto [0, 1].

    Each row holds ascending coefficients; leading coefficients below ``_NEGLIGIBLE`` times
    the row's largest are dropped, and the rows of each remaining degree share one batched
    eigenvalue call on their companion matrices. The real part of a complex root is kept
    too (clipped, it is still a point of the segment, so it can only add a candidate), and
    each root is improved by one Newton step, kept as a further candidate.

    Args:
        slope: Coefficients, shape (N, m + 1).

    Returns:
        Candidate points, shape (N, 2 m); 0 where a row has fewer roots.
    """
    rows, width = slope.shape
    found = np.zeros((rows, 2 * (width - 1)))
    size = np.abs(slope)
    significant = size > _NEGLIGIBLE * size.max(axis=1, keepdims=True)
    degree = np.where(
        significant.any(axis=1), width - 1 - np.argmax(significant[:, ::-1], axis=1), 0
    )
    for m in range(1, width):
        which = np.flatnonzero(degree == m)
        if which.size == 0:
            continue
        c = slope[which, : m + 1]
        companion = np.zeros((which.size, m, m))
        companion[:, np.arange(1, m), np.arange(m - 1)] = 1.0
        companion[:, :, -1] = -c[:, :m] / c[:, m : m + 1]
        u = np.clip(np.linalg.eigvals(companion).real, 0.0, 1.0)  # (N_m, m)
        value, derivative = _horner(c, u)
        # A near-zero derivative overflows the Newton step: the clip below keeps the root
        # in the segment, and the unpolished root u is a candidate too.
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = np.where(derivative != 0.0, value / derivative, 0.0)
        polished = np.clip(np.nan_to_num(u - step, nan=0.0), 0.0, 1.0)
        found[which, :m] = u
        found[which, width - 1 : width - 1 + m] = polished
    return found


#: A convex score of a joint quantity: values (any shape) and the joint of each (broadcast
#: with them) in, scores out; larger is worse.
_Score = Callable[[FloatArray, NDArray[np.intp]], FloatArray]


@functools.cache
def _bernstein(degree: int) -> FloatArray:
    """Matrix from power to Bernstein coefficients on [0, 1], shape (degree + 1, degree + 1).

    ``b_k = sum_{i <= k} C(k, i) / C(degree, i) a_i``; a polynomial on [0, 1] lies between
    its smallest and largest Bernstein coefficient (Farouki & Rajan, "On the numerical
    condition of polynomials in Bernstein form", CAGD 4(3), 1987).
    """
    matrix = np.zeros((degree + 1, degree + 1))
    for k in range(degree + 1):
        for i in range(k + 1):
            matrix[i, k] = math.comb(k, i) / math.comb(degree, i)
    return matrix


@dataclass(frozen=True)
class _Candidates:
    """Instants where a joint quantity may take its worst value, flat over segments and joints.

    Attributes:
        time: The instants [s] (a segment's end is its breakpoint exactly), shape (M,).
        value: The quantity there [unit], shape (M,).
        slope: Its time derivative there [unit/s], shape (M,).
        joint: The joint of each, shape (M,).
    """

    time: FloatArray
    value: FloatArray
    slope: FloatArray
    joint: NDArray[np.intp]


def _exact_candidates(ctx: _Context, order: int, score: _Score, fails: float) -> _Candidates:
    """Candidates that hold the exact worst score of the ``order``-th derivative, every segment.

    Every segment's two ends are candidates. A segment's interior can only matter when its
    Bernstein enclosure (a rigorous bound of the polynomial on the segment) scores above the
    best end or above ``fails`` (where a value starts to fail); for those (segment, joint)
    pairs the real roots of the derivative are added (:func:`_unit_roots`). So the largest
    score over the candidates is the exact largest over the whole trajectory, whatever the
    sampling rate, and no value that fails is left out; vectorised over segments and joints.

    Args:
        ctx: Check context.
        order: 0 position, 1 velocity, 2 acceleration, 3 jerk.
        score: Convex score per joint (larger is worse), so its largest value over an
            interval of values is at one of the interval's ends.
        fails: The score above which a value may fail.
    """
    knots = ctx.knots
    coefficients = ctx.derivatives[order]
    _, width, n = coefficients.shape
    h = np.diff(knots)
    scaled = coefficients * (h[:, None] ** np.arange(width, dtype=float))[:, :, None]
    powers = np.arange(width, dtype=float)[None, :, None]
    joints = np.arange(n)
    value = np.stack([scaled[:, 0, :], scaled.sum(axis=1)], axis=1)  # (K, 2, n): u = 0, 1
    if width == 1:
        slope = np.zeros_like(value)
    else:
        slope = np.stack([scaled[:, 1, :], (scaled * powers).sum(axis=1)], axis=1)
        slope /= h[:, None, None]
    time = np.broadcast_to(np.stack([knots[:-1], knots[1:]], axis=1)[:, :, None], value.shape)
    found = [
        (time.ravel(), value.ravel(), slope.ravel(), np.broadcast_to(joints, value.shape).ravel())
    ]
    if width > 2:
        best = float(np.max(score(value, joints)))
        threshold = min(best, fails)
        enclosure = np.einsum("kin,ij->kjn", scaled, _bernstein(width - 1))
        bound = np.maximum(
            score(enclosure.min(axis=1), joints), score(enclosure.max(axis=1), joints)
        )
        k, j = np.nonzero(bound >= threshold - round_off(threshold))
        if k.size:
            rows = scaled[k, :, j]  # (R, width)
            derivative = rows[:, 1:] * np.arange(1, width, dtype=float)
            u = _unit_roots(derivative)  # (R, c)
            inner_value, inner_slope = _horner(rows, u)
            length = h[k][:, None]
            found.append(
                (
                    (knots[k][:, None] + u * length).ravel(),
                    inner_value.ravel(),
                    (inner_slope / length).ravel(),
                    np.broadcast_to(j[:, None], u.shape).ravel(),
                )
            )
    times, values, slopes, which = (np.concatenate(parts) for parts in zip(*found, strict=True))
    return _Candidates(times, values, slopes, which)


@dataclass(frozen=True)
class _Jump:
    """A discontinuity of one joint quantity: at a breakpoint or against a boundary state."""

    order: int  # 0 position, 1 velocity, 2 acceleration
    time: float
    joint: int
    delta: float  # after minus before [rad.. or m..]
    size: float  # |delta| / threshold (> 1)
    source: str  # "" at a breakpoint, else "start state" / "end state"


def _thresholds(limits: JointLimits) -> list[FloatArray]:
    """Round-off scales per order: position range, velocity and acceleration limits."""
    return [limits.upper - limits.lower, limits.velocity, limits.acceleration]


def _breakpoint_jumps(
    derivatives: list[FloatArray], knots: FloatArray, limits: JointLimits
) -> list[_Jump]:
    """Jumps of position, velocity and acceleration between the two sides of inner breakpoints.

    Each side is evaluated exactly: segment k at its end ``tau = t_{k+1} - t_k`` against
    segment k + 1 at ``tau = 0``. A difference within :func:`round_off` is not a jump: the
    scale is the quantity's limit (the range for positions) plus the magnitudes summed on
    the left, the slope the sum of the two sides' slopes (moving a breakpoint by the time
    round-off changes the difference by at most that sum times the shift).
    """
    if len(knots) < 3:
        return []
    jumps: list[_Jump] = []
    h = np.diff(knots)[:-1]  # lengths of the segments that end at an inner breakpoint
    duration = float(knots[-1] - knots[0])
    scales = _thresholds(limits)
    for order in range(3):
        sides = []
        for coeffs in derivatives[order : order + 2]:
            left_rows = coeffs[:-1]  # (K - 1, d + 1, n)
            powers = h[:, None] ** np.arange(left_rows.shape[1])[None, :]  # (K - 1, d + 1)
            terms = left_rows * powers[:, :, None]
            sides.append((terms.sum(axis=1), coeffs[1:, 0, :], np.abs(terms).sum(axis=1)))
        (left, right, magnitude), (left_slope, right_slope, _) = sides
        delta = right - left
        threshold = round_off(
            scales[order][None, :] + magnitude,
            np.abs(left_slope) + np.abs(right_slope),
            duration,
        )
        rows, cols = np.nonzero(np.abs(delta) > threshold)
        for k, j in zip(rows.tolist(), cols.tolist(), strict=True):
            jumps.append(
                _Jump(
                    order,
                    float(knots[k + 1]),
                    j,
                    float(delta[k, j]),
                    float(abs(delta[k, j]) / threshold[k, j]),
                    "",
                )
            )
    return jumps


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
    scales = _thresholds(limits)
    return [
        None
        if target is None
        else tolerance + round_off(scales[order] + np.abs(target), slopes[order], duration)
        for order, target in enumerate(wanted)
    ]


def _boundary_jumps(
    state: BoundaryState,
    wanted: list[FloatArray | None],
    actual: list[FloatArray],
    time: float,
    limits: JointLimits,
    duration: float,
) -> list[_Jump]:
    """Jumps between a prescribed start/end state and the trajectory at that end.

    The robot is in the prescribed state before the start (after the end), so a difference in
    velocity, or in acceleration when one is prescribed, is a jump. A position difference is
    not counted as a jump: the ``start state`` / ``end state`` finding reports it. A difference
    within the state's own tolerance (plus round-off, :func:`state_allowance`) is not a jump
    either: it passes that finding too.

    Args:
        state: The prescribed state.
        wanted: Its validated q, qd, qdd (None where not prescribed).
        actual: The trajectory's q, qd, qdd, jerk at that end.
        time: The end's time [s].
        limits: The limits.
        duration: Trajectory duration [s].
    """
    tolerance = _tolerance(state.tolerance, "BoundaryState.tolerance")
    allowed = state_allowance(wanted, actual[1:], tolerance, limits, duration)
    jumps: list[_Jump] = []
    for order in (1, 2):
        target, threshold = wanted[order], allowed[order]
        if target is None or threshold is None:
            continue
        delta = actual[order] - target if state.at == "start" else target - actual[order]
        for j in np.flatnonzero(np.abs(delta) > threshold).tolist():
            jumps.append(
                _Jump(
                    order,
                    time,
                    j,
                    float(delta[j]),
                    float(abs(delta[j]) / threshold[j]),
                    f"{state.at} state",
                )
            )
    return jumps


def _jump_finding(
    quantity: str, jumps: list[_Jump], limits: JointLimits, names: tuple[str, ...]
) -> Finding | None:
    """A failing finding for ``quantity`` if a lower-order jump makes it unbounded."""
    order = _ORDER[quantity]
    causes = [jump for jump in jumps if jump.order < order]
    if not causes:
        return None
    worst = max(causes, key=lambda jump: (jump.order, jump.size))
    j = worst.joint
    jumped = _ORDER_NAME[worst.order]
    where = (
        f"(joint {names[j]!r})"
        if not worst.source
        else f"(joint {names[j]!r}) from the prescribed {worst.source}"
    )
    detail = (
        f"{jumped} jumps by {worst.delta:.4g} {limits.unit(jumped, j)} at "
        f"t = {worst.time:.6g} s {where}: needs unbounded {quantity}"
    )
    if len(causes) > 1:
        detail += f" ({len(causes) - 1} more jump{'s' if len(causes) > 2 else ''})"
    return _finding(
        quantity,
        "limit",
        math.inf,
        float(getattr(limits, _LIMIT_FIELD[quantity])[j]),
        time=worst.time,
        joint=names[j],
        unit=limits.unit(_UNIT_KEY[quantity], j),
        detail=detail,
    )


# ---------------------------------------------------------------------------- context


class _Kinematics:
    """Tool poses and twists at every instant any constraint asks for, in one batched call."""

    def __init__(self, robot: Robot, derivatives: list[FloatArray], knots: FloatArray) -> None:
        self._robot = robot
        self._derivatives = derivatives
        self._knots = knots
        self._pose_requests: list[FloatArray] = [np.empty(0)]
        self._twist_requests: list[FloatArray] = [np.empty(0)]
        self._times = np.empty(0)
        self._poses = np.empty((0, 4, 4))
        self._twist_times = np.empty(0)
        self._twists = np.empty((0, 6))

    def need(self, times: ArrayLike, *, twist: bool = False) -> None:
        """Ask for the tool pose (and twist) at these times [s]."""
        values = np.atleast_1d(np.asarray(times, dtype=float))
        self._pose_requests.append(values)
        if twist:
            self._twist_requests.append(values)

    def compute(self) -> None:
        """Evaluate every requested pose and twist (one batched robot call each)."""
        self._times = np.unique(np.concatenate(self._pose_requests))
        if self._times.size:
            q = _evaluate(self._derivatives[0], self._knots, self._times)
            self._poses = self._robot.tool_pose(q)
        self._twist_times = np.unique(np.concatenate(self._twist_requests))
        if self._twist_times.size:
            q = _evaluate(self._derivatives[0], self._knots, self._twist_times)
            qd = _evaluate(self._derivatives[1], self._knots, self._twist_times)
            jac = self._robot.jacobian(q)
            self._twists = np.einsum("mij,mj->mi", jac, qd)

    @staticmethod
    def _index(table: FloatArray, times: ArrayLike) -> NDArray[np.intp]:
        values = np.atleast_1d(np.asarray(times, dtype=float))
        index = np.searchsorted(table, values)
        if np.any(index >= table.size) or np.any(
            table[np.minimum(index, table.size - 1)] != values
        ):
            raise RuntimeError("kinematics asked at an instant that was not requested")
        return index

    def pose(self, times: ArrayLike) -> FloatArray:
        """Tool poses ``T_world_tool`` at requested times, shape (m, 4, 4)."""
        return self._poses[self._index(self._times, times)]

    def twist(self, times: ArrayLike) -> FloatArray:
        """Tool twists ``[v; w]`` (origin velocity [m/s], angular velocity [rad/s]), (m, 6)."""
        return self._twists[self._index(self._twist_times, times)]


@dataclass
class _Context:
    """Everything a constraint evaluation needs."""

    trajectory: Trajectory
    limits: JointLimits
    names: tuple[str, ...]
    knots: FloatArray
    derivatives: list[FloatArray]
    grid: FloatArray
    spacing: float
    kinematics: _Kinematics

    @property
    def duration(self) -> float:
        return self.trajectory.duration

    def phase(self, name: str) -> Phase | None:
        """The trajectory's phase ``name``, or None."""
        for phase in self.trajectory.phases:
            if phase.name == name:
                return phase
        return None

    def left_of(self, time: float) -> float:
        """The instant just before ``time`` (the largest float below it), unless at the end.

        Sampling is right-continuous; a window or phase that ends at a breakpoint must be
        judged by the segment that ends there, not by the one that starts there.
        """
        return time if time >= self.duration else float(np.nextafter(time, -np.inf))

    def window(self, start: float, end: float) -> FloatArray:
        """Sampled instants in [start, end], with both ends (the end from the left) [s]."""
        inside = self.grid[(self.grid >= start) & (self.grid < end)]
        last = self.left_of(end) if end > start else end
        return np.unique(np.concatenate([inside, [start, last]]))

    @functools.cached_property
    def peak_speed(self) -> float:
        """The fastest any joint moves [rad/s or m/s], exact on every segment."""
        speed = _exact_candidates(self, 1, lambda x, j: np.abs(x), math.inf)
        return float(np.max(np.abs(speed.value)))

    def state(self, time: float) -> list[FloatArray]:
        """Exact q, qd, qdd and jerk at one time, each shape (n,)."""
        at = np.array([min(max(time, 0.0), self.duration)])
        return [_evaluate(self.derivatives[r], self.knots, at)[0] for r in range(4)]

    def instant(self, time: float) -> float | None:
        """``time`` clipped onto [0, duration] if within round-off of it, else None."""
        if time < -TIME_TOLERANCE or time > self.duration + TIME_TOLERANCE:
            return None
        return min(max(float(time), 0.0), self.duration)


# -------------------------------------------------------------------- limit findings


def _limit_findings(
    quantities: tuple[str, ...],
    robot: Robot,
    ctx: _Context,
    jumps: list[_Jump],
) -> list[Finding]:
    """One finding per requested joint quantity: the worst joint and time.

    Position, velocity, acceleration and jerk are bounded exactly on every segment
    (:func:`_exact_candidates`), whatever the sampling rate; torque is sampled.
    """
    limits, names = ctx.limits, ctx.names
    findings: list[Finding] = []
    for quantity in quantities:
        unbounded = _jump_finding(quantity, jumps, limits, names)
        if unbounded is not None:
            findings.append(unbounded)
        elif quantity == "position":
            findings.append(_position_finding(ctx))
        elif quantity == "torque":
            sampled = [_evaluate(ctx.derivatives[r], ctx.knots, ctx.grid) for r in range(3)]
            torque = robot.inverse_dynamics(*sampled)
            findings.append(_torque_finding(ctx, torque))
        else:
            findings.append(_symmetric_finding(quantity, ctx))
    return findings


def _worst(ratio: FloatArray, excess: FloatArray) -> Any:
    """Index of the worst candidate.

    The largest ratio among the candidates that fail (excess > 0), or overall when none fails.
    """
    failing = excess > 0.0
    scores = np.where(failing, ratio, -np.inf) if np.any(failing) else ratio
    index = np.unravel_index(int(np.argmax(scores)), scores.shape)
    return index[0] if len(index) == 1 else tuple(int(i) for i in index)


def _position_finding(ctx: _Context) -> Finding:
    """Position margin: the smallest distance inside the nearer bound (negative outside)."""
    limits = ctx.limits
    lower, upper = limits.lower, limits.upper

    def score(x: FloatArray, j: NDArray[np.intp]) -> FloatArray:  # = -margin
        return np.maximum(lower[j] - x, x - upper[j])

    found = _exact_candidates(ctx, 0, score, 0.0)
    scores = score(found.value, found.joint)
    slack = round_off((upper - lower)[found.joint], found.slope, ctx.duration)
    i = _worst(scores, scores - slack)
    j = int(found.joint[i])
    x, time = float(found.value[i]), float(found.time[i])
    low, high = float(lower[j]), float(upper[j])
    near_upper = (high - x) <= (x - low)
    bound = high if near_upper else low
    side = "upper" if near_upper else "lower"
    unit = limits.unit("position", j)
    margin = 0.0 - float(scores[i])  # (not -0.0 on a bound)
    where = "inside" if margin >= 0.0 else "beyond"
    detail = (
        f"joint {ctx.names[j]!r} reaches {x:.6g} {unit}, {abs(margin):.4g} {unit} {where} its "
        f"{side} limit {bound:.6g} {unit}"
    )
    half = 0.5 * (high - low)
    return _finding(
        "position",
        "limit",
        x,
        bound,
        margin=margin,
        ratio=abs(x - 0.5 * (high + low)) / half,
        slack=float(slack[i]),
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


def _symmetric_finding(quantity: str, ctx: _Context) -> Finding:
    """Largest ``|x| / limit`` of velocity, acceleration or jerk, exactly over every segment."""
    bound = np.asarray(getattr(ctx.limits, _LIMIT_FIELD[quantity]))

    def score(x: FloatArray, j: NDArray[np.intp]) -> FloatArray:
        return np.abs(x) / bound[j]

    found = _exact_candidates(ctx, _ORDER[quantity], score, 1.0)
    magnitude = np.abs(found.value)
    limit = bound[found.joint]
    slack = round_off(limit, found.slope, ctx.duration)
    i = _worst(magnitude / limit, magnitude - limit - slack)
    return _magnitude_finding(
        quantity,
        ctx,
        float(magnitude[i]),
        float(found.time[i]),
        int(found.joint[i]),
        float(slack[i]),
    )


def _torque_finding(ctx: _Context, torque: FloatArray) -> Finding:
    """Largest ``|torque| / effort`` over the samples (torque is not a polynomial)."""
    bound = ctx.limits.effort
    magnitude = np.abs(torque)
    i, j = _worst(magnitude / bound, magnitude - bound - round_off(bound))
    return _magnitude_finding("torque", ctx, float(magnitude[i, j]), float(ctx.grid[i]), j, None)


def _magnitude_finding(
    quantity: str, ctx: _Context, value: float, time: float, j: int, slack: float | None
) -> Finding:
    """The finding for a symmetric quantity whose worst magnitude ``value`` is at ``time``."""
    limits = ctx.limits
    limit = float(getattr(limits, _LIMIT_FIELD[quantity])[j])
    ratio = value / limit
    unit = limits.unit(_UNIT_KEY[quantity], j)
    detail = (
        f"|{quantity}| of joint {ctx.names[j]!r} peaks at {value:.6g} {unit}, "
        f"{100.0 * ratio:.4g}% of its limit {limit:.6g} {unit}"
    )
    return _finding(
        quantity,
        "limit",
        value,
        limit,
        ratio=ratio,
        slack=slack,
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


# --------------------------------------------------------------------- task findings

_Evaluation = Callable[[], list[Finding]]


def _vector(value: ArrayLike, name: str, size: int) -> FloatArray:
    """A constraint's array as a finite float vector of ``size``, or InvalidInputError."""
    try:
        shape: tuple[int, ...] | None = np.shape(value)
    except ValueError:  # ragged nesting
        shape = None
    if shape != (size,):
        raise InvalidInputError(
            f"constraint {name} must be a finite vector of length {size}, got shape {shape}",
            name=name,
        )
    return as_vector(value, f"constraint {name}", size)


def _tolerance(value: object, name: str, unit: str = "") -> float:
    """A constraint's tolerance or time as a finite number >= 0 [unit], or InvalidInputError."""
    return as_number(value, name, unit, minimum=0.0)


def _unit_vector(value: ArrayLike, name: str) -> FloatArray:
    vector = _vector(value, name, 3)
    norm = float(np.linalg.norm(vector))
    if norm < 1e-12:
        raise InvalidInputError(f"constraint {name} must be a non-zero direction", name=name)
    return vector / norm


def _angle_between(a: FloatArray, b: FloatArray) -> FloatArray:
    """Angles between rows of unit vectors, shape (m,) [rad] (accurate near 0 and pi)."""
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.arctan2(cross, np.sum(a * b, axis=-1))


def _rotation_angle(R: FloatArray) -> FloatArray:
    """Rotation angles of rotation matrices, shape (...,) [rad] (accurate near 0 and pi)."""
    w = np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]],
        axis=-1,
    )
    sine = 0.5 * np.linalg.norm(w, axis=-1)
    cosine = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0)
    return np.arctan2(sine, cosine)


def _rotation_log(R: FloatArray) -> FloatArray:
    """Rotation vector (axis x angle) of one rotation matrix, shape (3,) [rad]."""
    angle = float(_rotation_angle(R))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < np.pi - 1e-6:
        return angle * w / (2.0 * math.sin(angle))
    # Near pi: the axis from the symmetric part, its sign from the skew part.
    B = 0.5 * (R + np.eye(3))
    column = int(np.argmax(np.diag(B)))
    axis = B[:, column] / math.sqrt(max(B[column, column], 1e-300))
    if float(np.dot(axis, w)) < 0.0:
        axis = -axis
    return angle * axis / np.linalg.norm(axis)


def _rotation_exp(vectors: FloatArray) -> FloatArray:
    """Rotation matrices of rotation vectors, (m, 3) -> (m, 3, 3) (Rodrigues)."""
    angle = np.linalg.norm(vectors, axis=-1)
    safe = np.where(angle > 1e-12, angle, 1.0)
    axis = vectors / safe[:, None]
    K = np.zeros((len(vectors), 3, 3))
    K[:, 0, 1], K[:, 0, 2] = -axis[:, 2], axis[:, 1]
    K[:, 1, 0], K[:, 1, 2] = axis[:, 2], -axis[:, 0]
    K[:, 2, 0], K[:, 2, 1] = -axis[:, 1], axis[:, 0]
    s = np.where(angle > 1e-12, np.sin(angle), 0.0)[:, None, None]
    c = np.where(angle > 1e-12, 1.0 - np.cos(angle), 0.0)[:, None, None]
    return np.eye(3)[None] + s * K + c * (K @ K)


def _missing(names: list[str], limits: list[float], units: list[str], why: str) -> _Evaluation:
    """Findings that fail with value ``inf`` because what they measure does not exist."""

    def evaluate() -> list[Finding]:
        return [
            _finding(n, "task", math.inf, lim, time=None, joint=None, unit=u, detail=why)
            for n, lim, u in zip(names, limits, units, strict=True)
        ]

    return evaluate


def _boundary_wanted(state: BoundaryState, n: int) -> list[FloatArray | None]:
    """A boundary state's validated q, qd, qdd (None where not prescribed), each shape (n,)."""
    if state.at not in ("start", "end"):
        raise InvalidInputError(
            f"BoundaryState.at must be 'start' or 'end', got {state.at!r}", name="at"
        )
    return [
        None if state.q is None else _vector(state.q, "BoundaryState.q", n),
        _vector(state.qd, "BoundaryState.qd", n),
        None if state.qdd is None else _vector(state.qdd, "BoundaryState.qdd", n),
    ]


def _boundary_state(
    state: BoundaryState, wanted: list[FloatArray | None], ctx: _Context
) -> _Evaluation:
    """``start state`` / ``end state``: largest deviation of q (if given), qd, qdd (if given).

    The finding passes when every prescribed quantity is within the state's tolerance plus
    round-off (:func:`state_allowance`, the rule the boundary jumps use too); it reports the
    largest deviation, or, when some quantity fails, the one that misses by the most.
    """
    time = 0.0 if state.at == "start" else ctx.duration
    tolerance = _tolerance(state.tolerance, "BoundaryState.tolerance")

    def evaluate() -> list[Finding]:
        actual = ctx.state(time)
        allowed = state_allowance(wanted, actual[1:], tolerance, ctx.limits, ctx.duration)
        best = (-math.inf, -1.0, 0, 0)  # (failing, error, order, joint), largest wins
        for order, target in enumerate(wanted):
            bound = allowed[order]
            if target is None or bound is None:
                continue
            error = np.abs(actual[order] - target)
            excess = error - bound
            j = int(np.argmax(excess)) if np.any(excess > 0.0) else int(np.argmax(error))
            key = (float(excess[j]) if excess[j] > 0.0 else -math.inf, float(error[j]))
            if key > best[:2]:
                best = (*key, order, j)
        _, value, order, j = best
        quantity = _ORDER_NAME[order]
        unit = ctx.limits.unit(quantity, j)
        target = wanted[order]
        bound = allowed[order]
        if target is None or bound is None:  # unreachable: qd is always prescribed
            raise RuntimeError("boundary state without a prescribed velocity")
        detail = (
            f"{_STATE_NAME[order]} of joint {ctx.names[j]!r} is {actual[order][j]:.6g} {unit}, "
            f"prescribed {target[j]:.6g} {unit}"
        )
        return [
            _finding(
                f"{state.at} state",
                "task",
                value,
                tolerance,
                time=time,
                joint=ctx.names[j],
                unit=unit,
                detail=detail,
                slack=float(bound[j]) - tolerance,
            )
        ]

    return evaluate


def _via_point(via: ViaPoint, ctx: _Context) -> _Evaluation:
    """``via point k``: the closest approach, as the largest joint distance, to ``via.q``."""
    target = _vector(via.q, "ViaPoint.q", ctx.limits.n)
    tolerance = _tolerance(via.tolerance, "ViaPoint.tolerance", "rad")
    name = f"via point {via.index}"

    def evaluate() -> list[Finding]:
        q = _evaluate(ctx.derivatives[0], ctx.knots, ctx.grid)
        distance = np.max(np.abs(q - target[None, :]), axis=1)
        i = int(np.argmin(distance))
        best = (float(distance[i]), float(ctx.grid[i]))
        # Exact minimum on the segments that can beat the best sample: the max-abs distance
        # is piecewise polynomial; its minimum lies at a segment end, a root or a stationary
        # point of one joint's error, or where two joints' errors are equal in magnitude.
        # Every instant lies within spacing / 2 of a sample, and the distance changes no
        # faster than the fastest joint: its exact peak speed (a factor 2 to spare).
        slack = ctx.peak_speed * ctx.spacing + 1e-15
        segment = _segments(ctx.knots, ctx.grid)
        close = np.argsort(distance, kind="stable")
        close = close[distance[close] <= best[0] + slack]
        candidates = list(dict.fromkeys(segment[close].tolist()))[: _MAX_REFINED // 4]
        for k in candidates:
            length = float(ctx.knots[k + 1] - ctx.knots[k])
            errors = ctx.derivatives[0][k].copy()  # (d + 1, n)
            errors[0] -= target
            polys = [errors[:, a] for a in range(errors.shape[1])]
            polys += [
                errors[:, a] + sign * errors[:, b]
                for a in range(errors.shape[1])
                for b in range(a + 1, errors.shape[1])
                for sign in (1.0, -1.0)
            ]
            taus = np.concatenate(
                [np.array([0.0, length])]
                + [_real_roots(p, length) for p in polys]
                + [_critical_points(p, length) for p in polys[: errors.shape[1]]]
            )
            values = np.max(
                np.abs(np.stack([_polyval(errors[:, a], taus) for a in range(errors.shape[1])])),
                axis=0,
            )
            m = int(np.argmin(values))
            if values[m] < best[0]:
                best = (float(values[m]), float(ctx.knots[k] + taus[m]))
        value, time = best
        q_at = _evaluate(ctx.derivatives[0], ctx.knots, np.array([time]))[0]
        j = int(np.argmax(np.abs(q_at - target)))
        unit = ctx.limits.unit("position", j)
        detail = (
            f"closest approach {value:.4g} {unit} at t = {time:.6g} s, largest on joint "
            f"{ctx.names[j]!r}"
        )
        return [
            _finding(
                name,
                "task",
                value,
                tolerance,
                time=time,
                joint=ctx.names[j],
                unit=unit,
                detail=detail,
            )
        ]

    return evaluate


def _tool_path(path: ToolPath, ctx: _Context) -> _Evaluation:
    """``tool path position`` and ``tool path orientation`` over the phase (or everything)."""
    names = ["tool path position", "tool path orientation"]
    tolerances = [
        _tolerance(path.position_tolerance, "ToolPath.position_tolerance", "m"),
        _tolerance(path.angle_tolerance, "ToolPath.angle_tolerance", "rad"),
    ]
    start = np.asarray(path.T_start, dtype=float)
    end = np.asarray(path.T_end, dtype=float)
    for label, T in (("T_start", start), ("T_end", end)):
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise InvalidInputError(f"ToolPath.{label} must be a finite 4x4 pose", name=label)
    if path.phase is None:
        window: Phase | None = Phase("all", 0.0, ctx.duration)
    else:
        window = ctx.phase(path.phase)
    if window is None:
        return _missing(names, tolerances, ["m", "rad"], f"phase {path.phase!r} missing")
    times = ctx.window(window.t_start, window.t_end)
    cap = None if path.speed is None else as_positive(path.speed, "ToolPath.speed", "m/s")
    ctx.kinematics.need(times, twist=cap is not None)

    def evaluate() -> list[Finding]:
        speed = [] if cap is None else [_speed_finding(ctx, times, cap)]
        poses = ctx.kinematics.pose(times)
        p = poses[:, :3, 3]
        p0, p1 = start[:3, 3], end[:3, 3]
        length = float(np.linalg.norm(p1 - p0))
        if length > 1e-12:
            axis = (p1 - p0) / length
            along = np.clip((p - p0) @ axis, 0.0, length)
            fraction = along / length
        else:  # no line to measure along: the fraction of the time instead
            span = max(window.t_end - window.t_start, 1e-300)
            along = np.zeros(len(times))
            fraction = np.clip((times - window.t_start) / span, 0.0, 1.0)
            axis = np.zeros(3)
        offset = np.linalg.norm(p - (p0 + along[:, None] * axis[None, :]), axis=1)
        gaps = [
            (float(np.max(offset)), float(times[int(np.argmax(offset))]), "off the line"),
            (float(np.linalg.norm(p[0] - p0)), float(times[0]), "from the start pose"),
            (float(np.linalg.norm(p[-1] - p1)), float(times[-1]), "from the end pose"),
        ]
        R0, R1 = start[:3, :3], end[:3, :3]
        turn = _rotation_log(R0.T @ R1)
        reference = R0[None] @ _rotation_exp(fraction[:, None] * turn[None, :])
        R = poses[:, :3, :3]
        angle = _rotation_angle(np.swapaxes(reference, 1, 2) @ R)
        turns = [
            (float(np.max(angle)), float(times[int(np.argmax(angle))]), "from the SLERP"),
            (float(_rotation_angle(R0.T @ R[0])), float(times[0]), "from the start orientation"),
            (float(_rotation_angle(R1.T @ R[-1])), float(times[-1]), "from the end orientation"),
        ]
        findings = []
        for name, tolerance, items, unit in (
            (names[0], tolerances[0], gaps, "m"),
            (names[1], tolerances[1], turns, "rad"),
        ):
            value, time, where = max(items, key=lambda item: item[0])
            findings.append(
                _finding(
                    name,
                    "task",
                    value,
                    tolerance,
                    time=time,
                    joint=None,
                    unit=unit,
                    detail=f"tool {value:.4g} {unit} {where} at t = {time:.6g} s",
                )
            )
        return findings + speed

    return evaluate


def _speed_finding(ctx: _Context, times: FloatArray, cap: float) -> Finding:
    """``tool speed``: the tool origin's fastest speed at ``times`` against ``cap`` [m/s].

    Sampled at the check's rate and every breakpoint (the speed is not a polynomial).
    """
    speed = np.linalg.norm(ctx.kinematics.twist(times)[:, :3], axis=1)
    worst = int(np.argmax(speed))
    value = float(speed[worst])
    return _finding(
        "tool speed",
        "task",
        value,
        cap,
        time=float(times[worst]),
        joint=None,
        unit="m/s",
        detail=f"tool origin at {value:.4g} m/s at t = {float(times[worst]):.6g} s "
        f"(cap {cap:.4g} m/s)",
    )


def _whole_speed(cap: float, ctx: _Context) -> _Evaluation:
    """The ``tool_speed`` cap of :func:`check` over the whole trajectory."""
    times = ctx.window(0.0, ctx.duration)
    ctx.kinematics.need(times, twist=True)
    return lambda: [_speed_finding(ctx, times, cap)]


def _strike_line(line: StrikeLine, ctx: _Context) -> _Evaluation:
    """The strike findings: window, position, speed, axis (if aligned) and contact."""
    names = ["strike window", "strike position", "strike speed"]
    position_tolerance = _tolerance(line.position_tolerance, "StrikeLine.position_tolerance", "m")
    tolerances = [
        STRIKE_WINDOW_TOLERANCE,
        position_tolerance,
        _tolerance(line.speed_tolerance, "StrikeLine.speed_tolerance"),
    ]
    units = ["s", "m", "-"]
    align = as_flag(line.align_axis, "StrikeLine.align_axis")
    if align:
        angle_tolerance = _tolerance(line.angle_tolerance, "StrikeLine.angle_tolerance", "rad")
        names.append("strike axis")
        tolerances.append(angle_tolerance)
        units.append("rad")
    names.append("contact")
    tolerances.append(position_tolerance)
    units.append("m")
    point = _vector(line.point, "StrikeLine.point", 3)
    direction = _unit_vector(line.direction, "StrikeLine.direction")
    speed = as_positive(line.speed, "StrikeLine.speed", "m/s")
    window = _tolerance(line.window, "StrikeLine.window", "s")
    delay = as_number(line.contact_delay, "StrikeLine.contact_delay", "s")
    phase = ctx.phase(line.phase)
    if phase is None:
        return _missing(names, tolerances, units, f"phase {line.phase!r} missing")
    t_contact = phase.t_start + delay
    contact_instant = ctx.instant(t_contact)
    times = ctx.window(phase.t_start, phase.t_end)
    ctx.kinematics.need(times, twist=True)
    if contact_instant is not None:
        ctx.kinematics.need([contact_instant])

    def evaluate() -> list[Finding]:
        findings = []
        gap = abs(phase.duration - window)
        findings.append(
            _finding(
                "strike window",
                "task",
                gap,
                STRIKE_WINDOW_TOLERANCE,
                time=phase.t_start,
                joint=None,
                unit="s",
                detail=(
                    f"phase {phase.name!r} lasts {phase.duration:.6g} s, the strike window "
                    f"{window:.6g} s"
                ),
            )
        )
        p = ctx.kinematics.pose(times)[:, :3, 3]
        schedule = point[None, :] + speed * (times - t_contact)[:, None] * direction[None, :]
        off = np.linalg.norm(p - schedule, axis=1)
        i = int(np.argmax(off))
        findings.append(
            _finding(
                "strike position",
                "task",
                float(off[i]),
                tolerances[1],
                time=float(times[i]),
                joint=None,
                unit="m",
                detail=f"tool {off[i]:.4g} m from its strike schedule at t = {times[i]:.6g} s",
            )
        )
        v = ctx.kinematics.twist(times)[:, :3]
        along = v @ direction
        lateral = np.linalg.norm(v - along[:, None] * direction[None, :], axis=1)
        speed_error = np.abs(along - speed) / speed
        side_error = lateral / speed
        i, k = int(np.argmax(speed_error)), int(np.argmax(side_error))
        if speed_error[i] >= side_error[k]:
            value, time = float(speed_error[i]), float(times[i])
            detail = (
                f"tool speed along the line {along[i]:.6g} m/s, commanded {speed:.6g} m/s, "
                f"at t = {time:.6g} s"
            )
        else:
            value, time = float(side_error[k]), float(times[k])
            detail = f"tool moves {lateral[k]:.4g} m/s across the line at t = {time:.6g} s"
        findings.append(
            _finding(
                "strike speed",
                "task",
                value,
                tolerances[2],
                time=time,
                joint=None,
                unit="-",
                detail=detail,
            )
        )
        if align:
            z = ctx.kinematics.pose(times)[:, :3, 2]
            angle = _angle_between(z, np.broadcast_to(direction, z.shape))
            i = int(np.argmax(angle))
            findings.append(
                _finding(
                    "strike axis",
                    "task",
                    float(angle[i]),
                    angle_tolerance,
                    time=float(times[i]),
                    joint=None,
                    unit="rad",
                    detail=(
                        f"tool z axis {np.degrees(angle[i]):.4g} deg off the strike direction "
                        f"at t = {times[i]:.6g} s"
                    ),
                )
            )
        if contact_instant is None:
            findings.append(
                _finding(
                    "contact",
                    "task",
                    math.inf,
                    tolerances[-1],
                    time=None,
                    joint=None,
                    unit="m",
                    detail=(
                        f"contact time {t_contact:.6g} s lies outside the trajectory "
                        f"[0, {ctx.duration:.6g}] s"
                    ),
                )
            )
        else:
            miss = float(np.linalg.norm(ctx.kinematics.pose(contact_instant)[0, :3, 3] - point))
            findings.append(
                _finding(
                    "contact",
                    "task",
                    miss,
                    tolerances[-1],
                    time=contact_instant,
                    joint=None,
                    unit="m",
                    detail=f"tool {miss:.4g} m from the contact point at t = {t_contact:.6g} s",
                )
            )
        return findings

    return evaluate


def _tool_contact(contact: ToolContact, ctx: _Context) -> _Evaluation:
    """``<label>`` (point), ``<label> axis`` and ``<label> velocity`` at one instant."""
    label = str(contact.label)
    position_tolerance = _tolerance(
        contact.position_tolerance, "ToolContact.position_tolerance", "m"
    )
    names, tolerances, units = [label], [position_tolerance], ["m"]
    position = _vector(contact.position, "ToolContact.position", 3)
    axis = None if contact.axis is None else _unit_vector(contact.axis, "ToolContact.axis")
    velocity = (
        None if contact.velocity is None else _vector(contact.velocity, "ToolContact.velocity", 3)
    )
    if axis is not None:
        names.append(f"{label} axis")
        angle_tolerance = _tolerance(contact.angle_tolerance, "ToolContact.angle_tolerance", "rad")
        tolerances.append(angle_tolerance)
        units.append("rad")
    if velocity is not None:
        names.append(f"{label} velocity")
        velocity_tolerance = _tolerance(
            contact.velocity_tolerance, "ToolContact.velocity_tolerance", "m/s"
        )
        tolerances.append(velocity_tolerance)
        units.append("m/s")
    if contact.time is not None:
        wanted = as_number(contact.time, "ToolContact.time", "s")
    elif contact.phase is not None:
        phase = ctx.phase(contact.phase)
        if phase is None:
            return _missing(names, tolerances, units, f"phase {contact.phase!r} missing")
        if contact.at not in ("start", "end"):
            raise InvalidInputError(
                f"ToolContact.at must be 'start' or 'end', got {contact.at!r}", name="at"
            )
        wanted = phase.t_start if contact.at == "start" else ctx.left_of(phase.t_end)
    else:
        raise InvalidInputError(
            f"ToolContact {label!r} names no instant: give time or phase", name="time"
        )
    instant = ctx.instant(wanted)
    if instant is None:
        return _missing(
            names,
            tolerances,
            units,
            f"instant {wanted:.6g} s lies outside the trajectory [0, {ctx.duration:.6g}] s",
        )
    ctx.kinematics.need([instant], twist=velocity is not None)
    offset = as_number(contact.offset, "ToolContact.offset", "m")

    def evaluate() -> list[Finding]:
        T = ctx.kinematics.pose(instant)[0]
        z = T[:3, 2]
        reached = T[:3, 3] + offset * z
        miss = float(np.linalg.norm(reached - position))
        findings = [
            _finding(
                label,
                "task",
                miss,
                tolerances[0],
                time=instant,
                joint=None,
                unit="m",
                detail=f"tool point {miss:.4g} m from its target at t = {instant:.6g} s",
            )
        ]
        if axis is not None:
            angle = float(_angle_between(z[None], axis[None])[0])
            findings.append(
                _finding(
                    f"{label} axis",
                    "task",
                    angle,
                    angle_tolerance,
                    time=instant,
                    joint=None,
                    unit="rad",
                    detail=f"tool z axis {np.degrees(angle):.4g} deg off the required axis",
                )
            )
        if velocity is not None:
            twist = ctx.kinematics.twist(instant)[0]
            moving = twist[:3] + np.cross(twist[3:], offset * z)
            error = float(np.linalg.norm(moving - velocity))
            findings.append(
                _finding(
                    f"{label} velocity",
                    "task",
                    error,
                    velocity_tolerance,
                    time=instant,
                    joint=None,
                    unit="m/s",
                    detail=(
                        f"tool point velocity ({', '.join(f'{v:.4g}' for v in moving)}) m/s, "
                        f"required ({', '.join(f'{v:.4g}' for v in velocity)}) m/s"
                    ),
                )
            )
        return findings

    return evaluate


# ------------------------------------------------------------------------------ check


def _target(target: Any) -> tuple[Robot, JointLimits, tuple[Any, ...]]:
    """Robot, limits and constraints of a robot or of a duck-typed problem."""
    if isinstance(target, Robot):
        return target, target.limits, ()
    robot = getattr(target, "robot", None)
    limits = getattr(target, "limits", None)
    constraints = getattr(target, "constraints", None)
    if not (isinstance(robot, Robot) and isinstance(limits, JointLimits) and callable(constraints)):
        raise InvalidInputError(
            "target must be a robots.Robot or a problem with .robot (a robots.Robot), .limits "
            f"(a robots.JointLimits) and .constraints(), got {type(target).__name__}",
            name="target",
        )
    if limits.n != robot.dof:
        raise InvalidInputError(
            f"the problem's limits cover {limits.n} joints, its robot has {robot.dof}",
            name="target",
        )
    listed = constraints()
    try:
        items = tuple(listed)
    except TypeError as exc:
        raise InvalidInputError(
            "target.constraints() must return an iterable of constraints, got "
            f"{type(listed).__name__}",
            name="target",
        ) from exc
    return robot, limits, items


def _quantities(quantities: Iterable[str] | None) -> tuple[str, ...]:
    if quantities is None:
        return QUANTITIES
    if isinstance(quantities, str):
        wanted: list[object] = [quantities]
    else:
        try:
            wanted = list(quantities)
        except TypeError as exc:
            raise InvalidInputError(
                f"quantities must be a name or names from {QUANTITIES}, got {quantities!r}",
                name="quantities",
            ) from exc
    for name in wanted:
        as_choice(name, "quantity", QUANTITIES)
    return tuple(q for q in QUANTITIES if q in wanted)


def check(
    trajectory: Trajectory,
    target: Robot | Checkable,
    *,
    rate: float = 1000.0,
    quantities: Iterable[str] | None = None,
    tool_speed: float | None = None,
) -> Report:
    """Check a trajectory against joint limits and, for a problem, its task constraints.

    Args:
        trajectory: The trajectory to judge (only its polynomials and phases are used).
        target: A :class:`robots.Robot` (its limits only), or a problem with ``.robot``,
            ``.limits`` and ``.constraints()`` (limits and every constraint).
        rate: Sampling rate [Hz], in (0, :data:`MAX_RATE`], for torques and task constraints
            (breakpoints and the instants just before them are always sampled); position,
            velocity, acceleration and jerk are bounded exactly on every segment whatever
            the rate. Rate times duration times joints must stay within
            :data:`optraj.validation.MAX_COUNT`.
        quantities: The limit findings to make, a subset of :data:`QUANTITIES`; all when None.
            Task findings are always made.
        tool_speed: A cap on the tool frame origin's speed over the whole trajectory [m/s]
            (what ``Toppra(tool_speed=...)`` promises): adds a ``tool speed`` finding,
            sampled at ``rate`` and every breakpoint; None for none. A
            :class:`problems.ToolPath` with ``speed`` adds one over its phase.

    Returns:
        The report: limit findings (one per quantity, worst joint and time) then task findings
        (``start state``, ``via point k``, ``tool path position``, ``strike speed``, ...).

    Raises:
        InvalidInputError: Not a Trajectory, an unusable target, a joint count that differs
            from the robot's, a bad rate, or a malformed or unknown constraint.
        UnknownNameError: An unknown quantity; lists the valid ones.
    """
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    robot, limits, constraints = _target(target)
    if trajectory.dof != robot.dof:
        raise InvalidInputError(
            f"the trajectory has {trajectory.dof} joints, robot {robot.name!r} has {robot.dof}",
            name="trajectory",
        )
    wanted = _quantities(quantities)
    rate = sampling_rate(rate, trajectory.duration, trajectory.dof)
    grid = trajectory.times(rate)
    knots = np.asarray(trajectory.breakpoints, dtype=float)
    derivatives = _derivatives(np.asarray(trajectory.coefficients, dtype=float), 4)
    ctx = _Context(
        trajectory=trajectory,
        limits=limits,
        names=limits.names,
        knots=knots,
        derivatives=derivatives,
        grid=grid,
        spacing=float(np.max(np.diff(grid))) if grid.size > 1 else trajectory.duration,
        kinematics=_Kinematics(robot, derivatives, knots),
    )

    jumps = _breakpoint_jumps(derivatives, knots, limits)
    evaluations: list[_Evaluation] = []
    if tool_speed is not None:
        evaluations.append(_whole_speed(as_positive(tool_speed, "tool_speed", "m/s"), ctx))
    for item in constraints:
        if isinstance(item, BoundaryState):
            prescribed = _boundary_wanted(item, limits.n)
            evaluations.append(_boundary_state(item, prescribed, ctx))
            time = 0.0 if item.at == "start" else trajectory.duration
            jumps.extend(
                _boundary_jumps(item, prescribed, ctx.state(time), time, limits, ctx.duration)
            )
        elif isinstance(item, ViaPoint):
            evaluations.append(_via_point(item, ctx))
        elif isinstance(item, ToolPath):
            evaluations.append(_tool_path(item, ctx))
        elif isinstance(item, StrikeLine):
            evaluations.append(_strike_line(item, ctx))
        elif isinstance(item, ToolContact):
            evaluations.append(_tool_contact(item, ctx))
        else:
            raise InvalidInputError(
                f"cannot check a constraint of type {type(item).__name__}; known: "
                "BoundaryState, ViaPoint, ToolPath, StrikeLine, ToolContact",
                name="constraints",
            )
    ctx.kinematics.compute()

    findings = _limit_findings(wanted, robot, ctx, jumps)
    seen: dict[str, int] = {}
    for evaluate in evaluations:
        for finding in evaluate():
            count = seen.get(finding.name, 0) + 1
            seen[finding.name] = count
            if count > 1:  # keep names unique, e.g. two contacts: "contact", "contact (2)"
                finding = replace(finding, name=f"{finding.name} ({count})")
            findings.append(finding)
    planner = trajectory.metadata.get("planner")
    info = TrajectoryInfo(
        duration=trajectory.duration,
        dof=trajectory.dof,
        segments=len(knots) - 1,
        samples=int(grid.size),
        rate=rate,
        planner=None if planner is None else str(planner),
        robot=robot.name,
    )
    return Report(tuple(findings), info)
