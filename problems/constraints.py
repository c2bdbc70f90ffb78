"""What a trajectory must satisfy besides the joint limits, as plain data.

Problems list these with ``constraints()``; the independent checker
(:func:`planners.check`) measures each one on a densely sampled trajectory. Planners may read
them too, but are judged only by the checker.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "BoundaryState",
    "Constraint",
    "StrikeLine",
    "ToolContact",
    "ToolPath",
    "ViaPoint",
]

FloatArray = NDArray[np.float64]

#: Default tolerances of a strike: 0.01 mm on the line, 0.1 % of the speed, 0.01 deg of axis.
#: (A 0.5 deg cue shot needs the tip within 0.3 mm of its line; these are far tighter.)
STRIKE_POSITION_TOLERANCE = 1e-5
STRIKE_SPEED_TOLERANCE = 1e-3
STRIKE_ANGLE_TOLERANCE = float(np.radians(0.01))


@dataclass(frozen=True, eq=False)
class BoundaryState:
    """The joint state at the start or end of the trajectory.

    Attributes:
        at: ``"start"`` or ``"end"``.
        q: Positions [rad or m], shape (n,), or None when any position will do.
        qd: Velocities [rad/s or m/s], shape (n,).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (n,), or None when not prescribed.
        tolerance: Allowed deviation of each entry [rad, rad/s, rad/s^2 or m, m/s, m/s^2].
    """

    at: Literal["start", "end"]
    q: FloatArray | None
    qd: FloatArray
    qdd: FloatArray | None = None
    tolerance: float = 1e-6


@dataclass(frozen=True, eq=False)
class ViaPoint:
    """A configuration the trajectory must pass within ``tolerance`` [rad or m] of."""

    q: FloatArray
    tolerance: float
    index: int


@dataclass(frozen=True, eq=False)
class ToolPath:
    """The tool follows the straight segment between two poses, orientation by SLERP.

    The tool is at ``T_start`` when the phase starts and at ``T_end`` when it ends; at every
    instant between, its origin lies within ``position_tolerance`` of the segment and its
    orientation within ``angle_tolerance`` of the SLERP between the end orientations at the
    same fraction of the way along the segment.

    Attributes:
        T_start: Start pose ``T_world_tool``, shape (4, 4).
        T_end: End pose, shape (4, 4).
        phase: Phase it applies to; the whole trajectory when None.
        position_tolerance: [m].
        angle_tolerance: [rad].
        speed: Cap on the tool origin's speed along the way [m/s], or None for none.
    """

    T_start: FloatArray
    T_end: FloatArray
    phase: str | None = None
    position_tolerance: float = 1e-4
    angle_tolerance: float = 1e-3
    speed: float | None = None


@dataclass(frozen=True, eq=False)
class StrikeLine:
    """The tool moves along a line at constant speed through a contact point.

    During the phase (the strike window) the tool origin follows
    ``p(t) = point + speed * (t - t_contact) * direction`` with ``t_contact = phase start +
    contact_delay``; its velocity is ``speed * direction``; with ``align_axis`` its z axis
    stays along ``direction`` (rotation about it is free).

    Attributes:
        phase: Name of the strike window phase.
        point: Contact point [m], shape (3,).
        direction: Unit direction, shape (3,).
        speed: Tool speed along the line [m/s].
        contact_delay: Time from the window's start to contact [s].
        window: Length of the window [s].
        align_axis: Whether the tool z axis must stay along the direction.
        position_tolerance: Allowed distance from the schedule [m].
        speed_tolerance: Allowed relative speed error [-].
        angle_tolerance: Allowed axis angle to the direction [rad].
        run_up: Distance along the line from the window's start to the contact point [m];
            None for ``speed * contact_delay``. A problem that knows it gives it, so that
            :attr:`entry_point` equals the problem's own entry point bit for bit.
    """

    phase: str
    point: FloatArray
    direction: FloatArray
    speed: float
    contact_delay: float
    window: float
    align_axis: bool = True
    position_tolerance: float = STRIKE_POSITION_TOLERANCE
    speed_tolerance: float = STRIKE_SPEED_TOLERANCE
    angle_tolerance: float = STRIKE_ANGLE_TOLERANCE
    run_up: float | None = None

    @property
    def entry_point(self) -> FloatArray:
        """Where the tool is when the window opens [m], shape (3,)."""
        run_up = (
            float(self.speed) * float(self.contact_delay) if self.run_up is None else self.run_up
        )
        return np.asarray(self.point) - float(run_up) * np.asarray(self.direction)


@dataclass(frozen=True, eq=False)
class ToolContact:
    """The tool is at a point (with an axis and a velocity) at one instant.

    The instant is ``time`` [s] when given, else the start or end of ``phase``. The point
    measured is the tool origin moved ``offset`` [m] along the tool z axis (a paddle meets the
    ball centre 0.01 m in front of its face).

    Attributes:
        position: Required point [m], shape (3,).
        axis: Required tool z direction, shape (3,), or None.
        velocity: Required velocity of the point [m/s], shape (3,), or None.
        time: Instant [s], or None to use the phase.
        phase: Phase whose start or end is the instant.
        at: ``"start"`` or ``"end"`` of the phase.
        offset: Offset of the point along tool z [m].
        label: Short name for reports, e.g. ``"grasp 0"``.
        position_tolerance: [m].
        angle_tolerance: [rad].
        velocity_tolerance: [m/s].
    """

    position: FloatArray
    axis: FloatArray | None = None
    velocity: FloatArray | None = None
    time: float | None = None
    phase: str | None = None
    at: Literal["start", "end"] = "end"
    offset: float = 0.0
    label: str = "contact"
    position_tolerance: float = 1e-6
    angle_tolerance: float = 1e-6
    velocity_tolerance: float = 1e-6


Constraint = BoundaryState | ViaPoint | ToolPath | StrikeLine | ToolContact
