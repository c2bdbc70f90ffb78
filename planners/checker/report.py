"""What a check returns: a :class:`Report` of :class:`Finding` objects, and what it accepts.

A finding is one measured limit or constraint (its worst value, where, and the verdict);
:func:`build_finding` makes one from a value and a bound, under the round-off rule of
:mod:`planners.checker.allowance`. :class:`Checkable` is the shape of a problem that
:func:`planners.checker.check` accepts.

Example::

    report = check(trajectory, problem)
    report["velocity"].ratio  # the worst velocity over its limit
    print(report.summary())   # a table of every finding
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.checker.allowance import round_off
from optraj.problems.constraints import Constraint
from optraj.robots import JointLimits, Robot
from optraj.validation import as_flag

__all__ = ["Checkable", "Finding", "Report", "TrajectoryInfo", "build_finding"]


class Checkable(Protocol):
    """What :func:`planners.checker.check` accepts besides a robot: a problem with these."""

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


def build_finding(
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
