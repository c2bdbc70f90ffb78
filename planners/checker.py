"""The independent trajectory checker: every limit and every task constraint, densely sampled.

:func:`check` judges any :class:`~planners.trajectory.Trajectory` against a robot's joint limits
and, for a problem, against the task constraints it lists (``problem.constraints()``). It trusts
nothing a planner says: it reads only the trajectory's breakpoints, polynomial coefficients and
phases (the planner name is copied into the summary, nothing else of the metadata is used).

How the worst values are found:

* Joint quantities (position, velocity, acceleration, jerk) are sampled at ``rate`` plus every
  breakpoint and the instant just before each; the worst samples are then refined exactly on
  their polynomial segments (end points and the real roots of the next derivative), so a peak
  between two samples is not missed.
* Torques are computed by inverse dynamics (Pinocchio's RNEA, through :class:`robots.Robot`) at
  every sample; they are not refined.
* Jumps are measured exactly, from the polynomial on each side of every breakpoint, and between
  a prescribed start or end velocity (and acceleration, when prescribed) and the trajectory's.
  A jump in a quantity makes every higher derivative unbounded: such findings fail with value
  ``inf``.
* Task constraints (tool on a line, strike schedule, contact) are measured from the tool frame
  pose and Jacobian, computed in one batched call over every instant needed.

Example::

    report = check(trajectory, problem)
    print(report)  # a table of every finding
    assert report.ok, report.violations
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.validation import as_positive
from planners.trajectory import TIME_TOLERANCE, Phase, Trajectory
from problems.constraints import (
    BoundaryState,
    Constraint,
    StrikeLine,
    ToolContact,
    ToolPath,
    ViaPoint,
)
from robots import JointLimits, Robot

__all__ = [
    "QUANTITIES",
    "STRIKE_WINDOW_TOLERANCE",
    "Checkable",
    "Finding",
    "Report",
    "TrajectoryInfo",
    "check",
]

FloatArray = NDArray[np.float64]

#: The limited joint quantities, in report order.
QUANTITIES: tuple[str, ...] = ("position", "velocity", "acceleration", "jerk", "torque")
#: Allowed difference between a strike phase's length and the commanded window [s].
STRIKE_WINDOW_TOLERANCE = 1e-6

#: A finding passes when ``margin >= -(RELATIVE_SLACK * scale + ABSOLUTE_SLACK)``.
RELATIVE_SLACK = 1e-9
ABSOLUTE_SLACK = 1e-12
#: Relative round-off allowed when comparing the two sides of a breakpoint.
_ROUND_OFF = 1e-12
#: Most polynomial segments examined exactly per quantity (the worst samples' segments).
_MAX_REFINED = 64

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
        ok: Whether the finding passes (margin >= -(1e-9 x scale + 1e-12)).
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
            number = float(raw)
            if math.isnan(number):
                raise InvalidInputError(f"finding {self.name!r}: {name} is NaN", name=name)
            object.__setattr__(self, name, number)
        object.__setattr__(self, "ok", bool(self.ok))


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
    scale: float | None = None,
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
        scale: Scale of the pass slack [unit]; ``|limit|`` when None.
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
    slack = RELATIVE_SLACK * abs(limit if scale is None else scale) + ABSOLUTE_SLACK
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


def _worst_sample(
    score: FloatArray,
    lipschitz: FloatArray,
    segment: NDArray[np.intp],
    spacing: float,
) -> list[tuple[int, int]]:
    """Segments and joints that may hold the worst value of a sampled score.

    Every instant of a segment lies within ``spacing / 2`` of a sample of that segment, so a
    segment can beat the best sample only if one of its samples comes within
    ``lipschitz * spacing`` of it (a factor 2 of safety on the sampled slope).

    Args:
        score: Sampled scores, shape (m, n); larger is worse.
        lipschitz: Largest sampled slope of the score per joint, shape (n,).
        segment: Segment of each sample, shape (m,).
        spacing: Largest gap between samples [s].

    Returns:
        Up to ``_MAX_REFINED`` (segment, joint) pairs, worst sample first.
    """
    best = float(np.max(score))
    rows, cols = np.nonzero(score >= best - (lipschitz * spacing + 1e-15)[None, :])
    order = np.argsort(-score[rows, cols], kind="stable")
    pairs: list[tuple[int, int]] = []
    seen: set[tuple[int, int]] = set()
    for i in order:
        pair = (int(segment[rows[i]]), int(cols[i]))
        if pair not in seen:
            seen.add(pair)
            pairs.append(pair)
            if len(pairs) >= _MAX_REFINED:
                break
    return pairs


# ---------------------------------------------------------------------------- jumps


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
    """Jump threshold scales per order: position range, velocity and acceleration limits."""
    return [limits.upper - limits.lower, limits.velocity, limits.acceleration]


def _breakpoint_jumps(
    derivatives: list[FloatArray], knots: FloatArray, limits: JointLimits
) -> list[_Jump]:
    """Jumps of position, velocity and acceleration between the two sides of inner breakpoints.

    Each side is evaluated exactly: segment k at its end ``tau = t_{k+1} - t_k`` against
    segment k + 1 at ``tau = 0``.
    """
    if len(knots) < 3:
        return []
    jumps: list[_Jump] = []
    h = np.diff(knots)[:-1]  # lengths of the segments that end at an inner breakpoint
    scales = _thresholds(limits)
    for order in range(3):
        coeffs = derivatives[order]
        left_rows = coeffs[:-1]  # (K - 1, d + 1, n)
        powers = h[:, None] ** np.arange(left_rows.shape[1])[None, :]  # (K - 1, d + 1)
        terms = left_rows * powers[:, :, None]
        left = terms.sum(axis=1)
        right = coeffs[1:, 0, :]
        delta = right - left
        threshold = (
            RELATIVE_SLACK * scales[order][None, :]
            + ABSOLUTE_SLACK
            + _ROUND_OFF * np.abs(terms).sum(axis=1)
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


def _boundary_jumps(
    state: BoundaryState, actual: list[FloatArray], time: float, limits: JointLimits
) -> list[_Jump]:
    """Jumps between a prescribed start/end state and the trajectory at that end.

    The robot is in the prescribed state before the start (after the end), so a difference in
    velocity, or in acceleration when one is prescribed, is a jump. A position difference is
    not counted as a jump: the ``start state`` / ``end state`` finding reports it. A difference
    within the state's own tolerance is not a jump either (it passes that finding too).
    """
    scales = _thresholds(limits)
    jumps: list[_Jump] = []
    for order, wanted in enumerate((None, state.qd, state.qdd)):
        if wanted is None:
            continue
        delta = actual[order] - wanted if state.at == "start" else wanted - actual[order]
        threshold = RELATIVE_SLACK * scales[order] + ABSOLUTE_SLACK + _ROUND_OFF * np.abs(wanted)
        threshold = np.maximum(threshold, float(state.tolerance))
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

    def state(self, time: float) -> list[FloatArray]:
        """Exact q, qd, qdd at one time, each shape (n,)."""
        at = np.array([min(max(time, 0.0), self.duration)])
        return [_evaluate(self.derivatives[r], self.knots, at)[0] for r in range(3)]

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
    """One finding per requested joint quantity: the worst joint and time."""
    limits, names, knots, derivs = ctx.limits, ctx.names, ctx.knots, ctx.derivatives
    times = ctx.grid
    segment = _segments(knots, times)
    values = {order: _evaluate(derivs[order], knots, times) for order in range(5)}
    findings: list[Finding] = []
    for quantity in quantities:
        unbounded = _jump_finding(quantity, jumps, limits, names)
        if unbounded is not None:
            findings.append(unbounded)
        elif quantity == "position":
            findings.append(_position_finding(ctx, values, segment))
        elif quantity == "torque":
            torque = robot.inverse_dynamics(values[0], values[1], values[2])
            findings.append(_symmetric_finding(quantity, ctx, torque, None, segment))
        else:
            order = _ORDER[quantity]
            findings.append(
                _symmetric_finding(quantity, ctx, values[order], values[order + 1], segment)
            )
    return findings


def _position_finding(
    ctx: _Context, values: dict[int, FloatArray], segment: NDArray[np.intp]
) -> Finding:
    """Position margin: the smallest distance inside the nearer bound (negative outside)."""
    limits, knots = ctx.limits, ctx.knots
    lower, upper = limits.lower, limits.upper
    q = values[0]
    score = np.maximum(lower - q, q - upper)  # = -margin, larger is worse
    i, j = np.unravel_index(int(np.argmax(score)), score.shape)
    best = (float(score[i, j]), int(j), float(ctx.grid[i]), float(q[i, j]))
    lipschitz = np.max(np.abs(values[1]), axis=0)
    for k, jj in _worst_sample(score, lipschitz, segment, ctx.spacing):
        coeffs = ctx.derivatives[0][k, :, jj]
        taus = _critical_points(coeffs, float(knots[k + 1] - knots[k]))
        xs = _polyval(coeffs, taus)
        scores = np.maximum(lower[jj] - xs, xs - upper[jj])
        m = int(np.argmax(scores))
        if scores[m] > best[0]:
            best = (float(scores[m]), jj, float(knots[k] + taus[m]), float(xs[m]))
    score_value, j, time, x = best
    low, high = float(lower[j]), float(upper[j])
    near_upper = (high - x) <= (x - low)
    bound = high if near_upper else low
    side = "upper" if near_upper else "lower"
    unit = limits.unit("position", j)
    margin = 0.0 - score_value  # (not -0.0 on a bound)
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
        scale=high - low,
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


def _symmetric_finding(
    quantity: str,
    ctx: _Context,
    samples: FloatArray,
    slopes: FloatArray | None,
    segment: NDArray[np.intp],
) -> Finding:
    """Largest ``|x| / limit`` over samples and joints, refined on polynomial segments.

    Args:
        quantity: velocity, acceleration, jerk or torque.
        ctx: Check context.
        samples: Sampled values, shape (m, n).
        slopes: Sampled time derivative, shape (m, n), for refinement; None for no refinement.
        segment: Segment of each sample, shape (m,).
    """
    limits, knots = ctx.limits, ctx.knots
    bound = np.asarray(getattr(limits, _LIMIT_FIELD[quantity]))
    score = np.abs(samples) / bound[None, :]
    i, j = np.unravel_index(int(np.argmax(score)), score.shape)
    best = (float(score[i, j]), int(j), float(ctx.grid[i]), float(abs(samples[i, j])))
    if slopes is not None:
        order = _ORDER[quantity]
        lipschitz = np.max(np.abs(slopes), axis=0) / bound
        for k, jj in _worst_sample(score, lipschitz, segment, ctx.spacing):
            coeffs = ctx.derivatives[order][k, :, jj]
            taus = _critical_points(coeffs, float(knots[k + 1] - knots[k]))
            xs = np.abs(_polyval(coeffs, taus))
            m = int(np.argmax(xs))
            if xs[m] / bound[jj] > best[0]:
                best = (float(xs[m] / bound[jj]), jj, float(knots[k] + taus[m]), float(xs[m]))
    ratio, j, time, value = best
    limit = float(bound[j])
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
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


# --------------------------------------------------------------------- task findings

_Evaluation = Callable[[], list[Finding]]


def _vector(value: ArrayLike, name: str, size: int) -> FloatArray:
    """A constraint's array as a finite float vector of ``size``, or InvalidInputError."""
    array = np.asarray(value, dtype=float)
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise InvalidInputError(
            f"constraint {name} must be a finite vector of length {size}, got shape {array.shape}",
            name=name,
        )
    return array


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


def _boundary_state(state: BoundaryState, ctx: _Context) -> _Evaluation:
    """``start state`` / ``end state``: largest deviation of q (if given), qd, qdd (if given)."""
    if state.at not in ("start", "end"):
        raise InvalidInputError(
            f"BoundaryState.at must be 'start' or 'end', got {state.at!r}", name="at"
        )
    n = ctx.limits.n
    wanted = [
        None if state.q is None else _vector(state.q, "BoundaryState.q", n),
        _vector(state.qd, "BoundaryState.qd", n),
        None if state.qdd is None else _vector(state.qdd, "BoundaryState.qdd", n),
    ]
    time = 0.0 if state.at == "start" else ctx.duration

    def evaluate() -> list[Finding]:
        actual = ctx.state(time)
        best = (-1.0, 0, 0)
        for order, target in enumerate(wanted):
            if target is None:
                continue
            error = np.abs(actual[order] - target)
            j = int(np.argmax(error))
            if error[j] > best[0]:
                best = (float(error[j]), order, j)
        value, order, j = best
        quantity = _ORDER_NAME[order]
        unit = ctx.limits.unit(quantity, j)
        target = wanted[order]
        assert target is not None
        detail = (
            f"{_STATE_NAME[order]} of joint {ctx.names[j]!r} is {actual[order][j]:.6g} {unit}, "
            f"prescribed {target[j]:.6g} {unit}"
        )
        return [
            _finding(
                f"{state.at} state",
                "task",
                value,
                float(state.tolerance),
                time=time,
                joint=ctx.names[j],
                unit=unit,
                detail=detail,
            )
        ]

    return evaluate


def _via_point(via: ViaPoint, ctx: _Context) -> _Evaluation:
    """``via point k``: the closest approach, as the largest joint distance, to ``via.q``."""
    target = _vector(via.q, "ViaPoint.q", ctx.limits.n)
    name = f"via point {via.index}"

    def evaluate() -> list[Finding]:
        q = _evaluate(ctx.derivatives[0], ctx.knots, ctx.grid)
        qd = _evaluate(ctx.derivatives[1], ctx.knots, ctx.grid)
        distance = np.max(np.abs(q - target[None, :]), axis=1)
        i = int(np.argmin(distance))
        best = (float(distance[i]), float(ctx.grid[i]))
        # Exact minimum on the segments that can beat the best sample: the max-abs distance
        # is piecewise polynomial; its minimum lies at a segment end, a root or a stationary
        # point of one joint's error, or where two joints' errors are equal in magnitude.
        slack = 2.0 * float(np.max(np.abs(qd))) * ctx.spacing + 1e-15
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
                float(via.tolerance),
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
    tolerances = [float(path.position_tolerance), float(path.angle_tolerance)]
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
    tolerances = [
        STRIKE_WINDOW_TOLERANCE,
        float(line.position_tolerance),
        float(line.speed_tolerance),
    ]
    units = ["s", "m", "-"]
    if line.align_axis:
        names.append("strike axis")
        tolerances.append(float(line.angle_tolerance))
        units.append("rad")
    names.append("contact")
    tolerances.append(float(line.position_tolerance))
    units.append("m")
    point = _vector(line.point, "StrikeLine.point", 3)
    direction = _unit_vector(line.direction, "StrikeLine.direction")
    speed = float(line.speed)
    if not (math.isfinite(speed) and speed > 0.0):
        raise InvalidInputError(f"StrikeLine.speed must be > 0 m/s, got {speed!r}", name="speed")
    phase = ctx.phase(line.phase)
    if phase is None:
        return _missing(names, tolerances, units, f"phase {line.phase!r} missing")
    t_contact = phase.t_start + float(line.contact_delay)
    contact_instant = ctx.instant(t_contact)
    times = ctx.window(phase.t_start, phase.t_end)
    ctx.kinematics.need(times, twist=True)
    if contact_instant is not None:
        ctx.kinematics.need([contact_instant])

    def evaluate() -> list[Finding]:
        findings = []
        gap = abs(phase.duration - float(line.window))
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
                    f"{float(line.window):.6g} s"
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
        if line.align_axis:
            z = ctx.kinematics.pose(times)[:, :3, 2]
            angle = _angle_between(z, np.broadcast_to(direction, z.shape))
            i = int(np.argmax(angle))
            findings.append(
                _finding(
                    "strike axis",
                    "task",
                    float(angle[i]),
                    float(line.angle_tolerance),
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
    names, tolerances, units = [label], [float(contact.position_tolerance)], ["m"]
    position = _vector(contact.position, "ToolContact.position", 3)
    axis = None if contact.axis is None else _unit_vector(contact.axis, "ToolContact.axis")
    velocity = (
        None if contact.velocity is None else _vector(contact.velocity, "ToolContact.velocity", 3)
    )
    if axis is not None:
        names.append(f"{label} axis")
        tolerances.append(float(contact.angle_tolerance))
        units.append("rad")
    if velocity is not None:
        names.append(f"{label} velocity")
        tolerances.append(float(contact.velocity_tolerance))
        units.append("m/s")
    if contact.time is not None:
        wanted = float(contact.time)
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
    offset = float(contact.offset)

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
                    float(contact.angle_tolerance),
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
                    float(contact.velocity_tolerance),
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
    return robot, limits, tuple(constraints())


def _quantities(quantities: Iterable[str] | None) -> tuple[str, ...]:
    if quantities is None:
        return QUANTITIES
    wanted = [quantities] if isinstance(quantities, str) else list(quantities)
    for name in wanted:
        if name not in QUANTITIES:
            raise UnknownNameError("quantity", str(name), QUANTITIES)
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
        rate: Sampling rate [Hz]; breakpoints and the instants just before them are always
            sampled, and joint quantities are refined exactly on their polynomials.
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
    grid = trajectory.times(rate)  # validates the rate
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
            evaluations.append(_boundary_state(item, ctx))
            time = 0.0 if item.at == "start" else trajectory.duration
            jumps.extend(_boundary_jumps(item, ctx.state(time), time, limits))
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
        rate=float(rate),
        planner=None if planner is None else str(planner),
        robot=robot.name,
    )
    return Report(tuple(findings), info)
