"""A joint-space move through a sequence of configurations."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.problems.common import check_robot, joint_state, non_negative, resolve_limits
from optraj.problems.constraints import BoundaryState, Constraint, ViaPoint
from optraj.problems.point_to_point import is_still, still_error
from optraj.robots import JointLimits, Robot
from optraj.validation import as_array, as_duration, as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["Waypoints"]


@dataclass(frozen=True, eq=False)
class Waypoints:
    """Move through waypoints, starting and ending at rest.

    Attributes:
        robot: The robot.
        waypoints: Configurations [rad or m], shape (k, n), k >= 2; the first is the start,
            the last the goal.
        segment_durations: Time of each of the k - 1 segments [s], or None to take them from
            the limits.
        via_tolerance: How close [rad or m] the trajectory must pass to the inner waypoints;
            None when blends may cut corners (checked only when given).
        limits: Limits to plan for; the robot's when None.
        tolerance: Allowed start/end state deviation for the checker.
    """

    robot: Robot
    waypoints: FloatArray
    segment_durations: FloatArray | None = None
    via_tolerance: float | None = None
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__post_init__)
    tolerance: float = 1e-6

    def __post_init__(self) -> None:
        limits = resolve_limits(check_robot(self.robot), self.limits)
        points = as_array(self.waypoints, "waypoints", (None, limits.n))
        if points.shape[0] < 2:
            raise InvalidInputError(
                f"waypoints needs at least 2 configurations, got {points.shape[0]}",
                name="waypoints",
            )
        for k, q in enumerate(points):
            limits.check_position(q, tolerance=1e-9, context=f"waypoint {k}")
        set_ = object.__setattr__
        set_(self, "limits", limits)
        set_(self, "waypoints", points)
        if self.segment_durations is not None:
            durations = as_vector(self.segment_durations, "segment_durations", points.shape[0] - 1)
            for k, duration in enumerate(durations):
                as_duration(duration, f"segment_durations[{k}]")
            set_(self, "segment_durations", durations)
        if self.via_tolerance is not None:
            set_(self, "via_tolerance", non_negative(self.via_tolerance, "via_tolerance", "rad"))
        set_(self, "tolerance", non_negative(self.tolerance, "tolerance", ""))
        joint_state(limits, points[0], None, None, "start")

    @property
    def still(self) -> bool:
        """Whether every waypoint equals the first: no joint moves more than STILL_TOLERANCE."""
        points = np.asarray(self.waypoints)
        return is_still(points[0], points)

    def require_motion(
        self,
        planner: str,
        *,
        reason: str = "so the fastest move lasts 0 s",
        remedy: str = "give segment_durations to hold still",
    ) -> None:
        """Refuse, for ``planner``, waypoints that all equal the first and no segment_durations.

        The rule of :meth:`problems.PointToPoint.require_motion` for a sequence of moves.

        Args:
            planner: Name of the planner, for the message.
            reason: Why a still sequence cannot be planned, for the message.
            remedy: What to do instead, for the message.

        Raises:
            InvalidInputError: Naming ``waypoints``, saying to give segment_durations to
                hold still.
        """
        if self.segment_durations is None and self.still:
            raise still_error(
                planner,
                what="every waypoint equals the first",
                name="waypoints",
                reason=reason,
                remedy=remedy,
            )

    def constraints(self) -> tuple[Constraint, ...]:
        """Rest at the first and last waypoints; the inner ones when via_tolerance is set."""
        n = self.limits.n
        points = np.asarray(self.waypoints)
        items: list[Constraint] = [
            BoundaryState("start", points[0], np.zeros(n), None, self.tolerance)
        ]
        if self.via_tolerance is not None:
            items.extend(
                ViaPoint(points[k], float(self.via_tolerance), k) for k in range(1, len(points) - 1)
            )
        items.append(BoundaryState("end", points[-1], np.zeros(n), None, self.tolerance))
        return tuple(items)
