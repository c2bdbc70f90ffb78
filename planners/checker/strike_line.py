"""The strike findings of a :class:`problems.StrikeLine`: window, position, speed, axis, contact.

Over the strike phase the tool frame origin must follow its schedule
``point + speed * (t - t_contact) * direction`` (``strike position``) at the commanded speed
along the line and none across it (``strike speed``, relative), with the tool z axis along
the direction when ``align_axis`` (``strike axis``); the phase must last the strike window
(``strike window``) and the tool must be at the point at the contact instant (``contact``).
Sampled at the check's rate and every breakpoint of the phase.

Example::

    evaluations.append(strike_line_check(line, ctx))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.report import Finding
from optraj.planners.checker.rotations import angle_between
from optraj.planners.checker.task import (
    Evaluation,
    constraint_direction,
    constraint_tolerance,
    constraint_vector,
    missing_findings,
    task_finding,
)
from optraj.planners.trajectory import Phase
from optraj.problems.constraints import StrikeLine
from optraj.validation import as_flag, as_number, as_positive

__all__ = ["STRIKE_WINDOW_TOLERANCE", "strike_line_check"]

FloatArray = NDArray[np.float64]

#: Allowed difference between a strike phase's length and the commanded window [s].
STRIKE_WINDOW_TOLERANCE = 1e-6


@dataclass(frozen=True)
class _Strike:
    """A strike line, validated.

    Attributes:
        position_tolerance: Tolerance of the schedule and of the contact [m].
        speed_tolerance: Relative tolerance of the speed [-].
        angle_tolerance: Tolerance of the tool axis [rad], or None when not aligned.
        point: The contact point [m], shape (3,).
        direction: The unit strike direction, shape (3,).
        speed: The commanded tool speed along the line [m/s].
        window: The commanded length of the strike phase [s].
        delay: Time from the start of the strike phase to the contact [s].
    """

    position_tolerance: float
    speed_tolerance: float
    angle_tolerance: float | None
    point: FloatArray
    direction: FloatArray
    speed: float
    window: float
    delay: float

    @classmethod
    def of(cls, line: StrikeLine) -> _Strike:
        """The validated fields of ``line``; InvalidInputError names a malformed one."""
        return cls(
            position_tolerance=constraint_tolerance(
                line.position_tolerance, "StrikeLine.position_tolerance", "m"
            ),
            speed_tolerance=constraint_tolerance(
                line.speed_tolerance, "StrikeLine.speed_tolerance"
            ),
            angle_tolerance=(
                constraint_tolerance(line.angle_tolerance, "StrikeLine.angle_tolerance", "rad")
                if as_flag(line.align_axis, "StrikeLine.align_axis")
                else None
            ),
            point=constraint_vector(line.point, "StrikeLine.point", 3),
            direction=constraint_direction(line.direction, "StrikeLine.direction"),
            speed=as_positive(line.speed, "StrikeLine.speed", "m/s"),
            window=constraint_tolerance(line.window, "StrikeLine.window", "s"),
            delay=as_number(line.contact_delay, "StrikeLine.contact_delay", "s"),
        )

    def expected(self) -> list[tuple[str, float, str]]:
        """(name, tolerance, unit) of each strike finding, in report order."""
        expected = [
            ("strike window", STRIKE_WINDOW_TOLERANCE, "s"),
            ("strike position", self.position_tolerance, "m"),
            ("strike speed", self.speed_tolerance, "-"),
        ]
        if self.angle_tolerance is not None:
            expected.append(("strike axis", self.angle_tolerance, "rad"))
        return [*expected, ("contact", self.position_tolerance, "m")]


@dataclass(frozen=True)
class _Instants:
    """Where a strike is measured on the trajectory.

    Attributes:
        phase: The strike phase.
        t_contact: The contact time [s].
        contact: ``t_contact`` on the trajectory, or None when outside it.
        times: The sampled instants of the phase [s].
    """

    phase: Phase
    t_contact: float
    contact: float | None
    times: FloatArray


def strike_line_check(line: StrikeLine, ctx: CheckContext) -> Evaluation:
    """The strike findings: window, position, speed, axis (if aligned) and contact."""
    strike = _Strike.of(line)
    phase = ctx.phase(line.phase)
    if phase is None:
        return missing_findings(strike.expected(), f"phase {line.phase!r} missing")
    t_contact = phase.t_start + strike.delay
    contact_instant = ctx.instant(t_contact)
    times = ctx.window(phase.t_start, phase.t_end)
    ctx.kinematics.need(times, twist=True)
    if contact_instant is not None:
        ctx.kinematics.need([contact_instant])
    at = _Instants(phase, t_contact, contact_instant, times)
    return lambda: _strike_findings(strike, at, ctx)


def _strike_findings(strike: _Strike, at: _Instants, ctx: CheckContext) -> list[Finding]:
    """Every strike finding, once the tool kinematics are computed."""
    findings = [
        _window_finding(strike, at.phase),
        _position_finding(strike, at, ctx),
        _speed_finding(strike, at.times, ctx),
    ]
    if strike.angle_tolerance is not None:
        findings.append(_axis_finding(strike, strike.angle_tolerance, at.times, ctx))
    findings.append(_contact_finding(strike, at, ctx))
    return findings


def _window_finding(strike: _Strike, phase: Phase) -> Finding:
    """``strike window``: the strike phase's length against the commanded window [s]."""
    gap = abs(phase.duration - strike.window)
    detail = (
        f"phase {phase.name!r} lasts {phase.duration:.6g} s, the strike window "
        f"{strike.window:.6g} s"
    )
    return task_finding("strike window", gap, STRIKE_WINDOW_TOLERANCE, phase.t_start, "s", detail)


def _position_finding(strike: _Strike, at: _Instants, ctx: CheckContext) -> Finding:
    """``strike position``: the tool origin's largest distance from its schedule [m]."""
    times = at.times
    p = ctx.kinematics.pose(times)[:, :3, 3]
    run = strike.speed * (times - at.t_contact)[:, None] * strike.direction[None, :]
    schedule = strike.point[None, :] + run
    off = np.linalg.norm(p - schedule, axis=1)
    i = int(np.argmax(off))
    detail = f"tool {off[i]:.4g} m from its strike schedule at t = {times[i]:.6g} s"
    return task_finding(
        "strike position", float(off[i]), strike.position_tolerance, float(times[i]), "m", detail
    )


def _speed_finding(strike: _Strike, times: FloatArray, ctx: CheckContext) -> Finding:
    """``strike speed``: the larger relative speed error, along the line or across it [-]."""
    direction, speed = strike.direction, strike.speed
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
    return task_finding("strike speed", value, strike.speed_tolerance, time, "-", detail)


def _axis_finding(
    strike: _Strike, tolerance: float, times: FloatArray, ctx: CheckContext
) -> Finding:
    """``strike axis``: the tool z axis's largest angle from the strike direction [rad]."""
    z = ctx.kinematics.pose(times)[:, :3, 2]
    angle = angle_between(z, np.broadcast_to(strike.direction, z.shape))
    i = int(np.argmax(angle))
    detail = (
        f"tool z axis {np.degrees(angle[i]):.4g} deg off the strike direction "
        f"at t = {times[i]:.6g} s"
    )
    return task_finding("strike axis", float(angle[i]), tolerance, float(times[i]), "rad", detail)


def _contact_finding(strike: _Strike, at: _Instants, ctx: CheckContext) -> Finding:
    """``contact``: the tool origin's distance from the point at the contact instant [m]."""
    tolerance = strike.position_tolerance
    if at.contact is None:
        detail = (
            f"contact time {at.t_contact:.6g} s lies outside the trajectory "
            f"[0, {ctx.duration:.6g}] s"
        )
        return task_finding("contact", math.inf, tolerance, None, "m", detail)
    instant = at.contact
    miss = float(np.linalg.norm(ctx.kinematics.pose(instant)[0, :3, 3] - strike.point))
    detail = f"tool {miss:.4g} m from the contact point at t = {at.t_contact:.6g} s"
    return task_finding("contact", miss, tolerance, instant, "m", detail)
