"""The findings of a :class:`problems.ToolContact`: a tool point, axis and velocity at an instant.

At one instant (a time, or the start or end of a phase) the tool point ``offset`` along the
tool z axis must be at ``position`` (finding ``<label>``), the z axis along ``axis`` when
given (``<label> axis``) and the point moving at ``velocity`` when given
(``<label> velocity``).

Example::

    evaluations.append(tool_contact_check(contact, ctx))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
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
from optraj.problems.constraints import ToolContact
from optraj.validation import as_number

__all__ = ["tool_contact_check"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class _Contact:
    """A tool contact, validated.

    Attributes:
        label: The name of its findings.
        position_tolerance: Tolerance of the tool point [m].
        position: Where the tool point must be [m], shape (3,).
        axis: The unit direction of the tool z axis, shape (3,), or None.
        velocity: The tool point's velocity [m/s], shape (3,), or None.
        angle_tolerance: Tolerance of the axis [rad], None without an axis.
        velocity_tolerance: Tolerance of the velocity [m/s], None without a velocity.
    """

    label: str
    position_tolerance: float
    position: FloatArray
    axis: FloatArray | None
    velocity: FloatArray | None
    angle_tolerance: float | None
    velocity_tolerance: float | None

    @classmethod
    def of(cls, contact: ToolContact) -> _Contact:
        """The validated fields of ``contact``; InvalidInputError names a malformed one."""
        return cls(
            label=str(contact.label),
            position_tolerance=constraint_tolerance(
                contact.position_tolerance, "ToolContact.position_tolerance", "m"
            ),
            position=constraint_vector(contact.position, "ToolContact.position", 3),
            axis=(
                None
                if contact.axis is None
                else constraint_direction(contact.axis, "ToolContact.axis")
            ),
            velocity=(
                None
                if contact.velocity is None
                else constraint_vector(contact.velocity, "ToolContact.velocity", 3)
            ),
            angle_tolerance=(
                None
                if contact.axis is None
                else constraint_tolerance(
                    contact.angle_tolerance, "ToolContact.angle_tolerance", "rad"
                )
            ),
            velocity_tolerance=(
                None
                if contact.velocity is None
                else constraint_tolerance(
                    contact.velocity_tolerance, "ToolContact.velocity_tolerance", "m/s"
                )
            ),
        )

    def expected(self) -> list[tuple[str, float, str]]:
        """(name, tolerance, unit) of each finding of the contact, in report order."""
        expected = [(self.label, self.position_tolerance, "m")]
        if self.angle_tolerance is not None:
            expected.append((f"{self.label} axis", self.angle_tolerance, "rad"))
        if self.velocity_tolerance is not None:
            expected.append((f"{self.label} velocity", self.velocity_tolerance, "m/s"))
        return expected


def tool_contact_check(contact: ToolContact, ctx: CheckContext) -> Evaluation:
    """``<label>`` (point), ``<label> axis`` and ``<label> velocity`` at one instant."""
    found = _Contact.of(contact)
    wanted = _wanted_time(contact, found.label, ctx)
    if wanted is None:
        return missing_findings(found.expected(), f"phase {contact.phase!r} missing")
    instant = ctx.instant(wanted)
    if instant is None:
        why = f"instant {wanted:.6g} s lies outside the trajectory [0, {ctx.duration:.6g}] s"
        return missing_findings(found.expected(), why)
    ctx.kinematics.need([instant], twist=found.velocity is not None)
    offset = as_number(contact.offset, "ToolContact.offset", "m")
    return lambda: _contact_findings(found, instant, offset, ctx)


def _wanted_time(contact: ToolContact, label: str, ctx: CheckContext) -> float | None:
    """The contact's instant [s]: its time, or its phase's start or end; None if no phase.

    Raises:
        InvalidInputError: ``at`` is neither ``"start"`` nor ``"end"``, or neither a time
            nor a phase is given.
    """
    if contact.time is not None:
        return as_number(contact.time, "ToolContact.time", "s")
    if contact.phase is None:
        raise InvalidInputError(
            f"ToolContact {label!r} names no instant: give time or phase", name="time"
        )
    phase = ctx.phase(contact.phase)
    if phase is None:
        return None
    if contact.at not in ("start", "end"):
        raise InvalidInputError(
            f"ToolContact.at must be 'start' or 'end', got {contact.at!r}", name="at"
        )
    return phase.t_start if contact.at == "start" else ctx.left_of(phase.t_end)


def _contact_findings(
    contact: _Contact, instant: float, offset: float, ctx: CheckContext
) -> list[Finding]:
    """Every finding of the contact at ``instant`` [s], tool point ``offset`` [m] along z."""
    label = contact.label
    T = ctx.kinematics.pose(instant)[0]
    z = T[:3, 2]
    reached = T[:3, 3] + offset * z
    miss = float(np.linalg.norm(reached - contact.position))
    detail = f"tool point {miss:.4g} m from its target at t = {instant:.6g} s"
    findings = [task_finding(label, miss, contact.position_tolerance, instant, "m", detail)]
    if contact.axis is not None and contact.angle_tolerance is not None:
        angle = float(angle_between(z[None], contact.axis[None])[0])
        detail = f"tool z axis {np.degrees(angle):.4g} deg off the required axis"
        tolerance = contact.angle_tolerance
        findings.append(task_finding(f"{label} axis", angle, tolerance, instant, "rad", detail))
    if contact.velocity is not None and contact.velocity_tolerance is not None:
        twist = ctx.kinematics.twist(instant)[0]
        moving = twist[:3] + np.cross(twist[3:], offset * z)
        error = float(np.linalg.norm(moving - contact.velocity))
        detail = (
            f"tool point velocity ({', '.join(f'{v:.4g}' for v in moving)}) m/s, "
            f"required ({', '.join(f'{v:.4g}' for v in contact.velocity)}) m/s"
        )
        tolerance = contact.velocity_tolerance
        findings.append(task_finding(f"{label} velocity", error, tolerance, instant, "m/s", detail))
    return findings
