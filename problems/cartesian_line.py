"""A straight-line tool motion between two poses."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.problems.common import (
    MAX_TOOL_SPEED,
    check_robot,
    positive,
    positive_fields,
    resolve_limits,
)
from optraj.problems.constraints import BoundaryState, Constraint, ToolPath
from optraj.problems.point_to_point import STILL_TOLERANCE, still_error
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.validation import as_duration, as_transform, as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["CartesianLine"]


@dataclass(frozen=True, eq=False)
class CartesianLine:
    """Move the tool on a straight line from one pose to another, orientation by SLERP.

    Attributes:
        robot: The robot.
        T_start: Start pose ``T_world_tool``, shape (4, 4).
        T_goal: Goal pose ``T_world_tool``, shape (4, 4).
        q_start: Start configuration [rad or m], shape (n,), which must put the tool at
            T_start; found by IK near the home pose when None.
        duration: Fixed duration [s], or None.
        speed: Tool speed cap along the line [m/s], or None.
        limits: Limits to plan for; the robot's when None.
        position_tolerance: Allowed distance of the tool from the line [m].
        angle_tolerance: Allowed orientation error from the SLERP [rad].
    """

    robot: Robot
    T_start: ArrayLike
    T_goal: ArrayLike
    q_start: FloatArray = None  # type: ignore[assignment]  # None: resolved in __post_init__
    duration: float | None = None
    speed: float | None = None
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__post_init__)
    position_tolerance: float = 1e-4
    angle_tolerance: float = 1e-3

    def __post_init__(self) -> None:
        robot = check_robot(self.robot)
        limits = resolve_limits(robot, self.limits)
        start = as_transform(self.T_start, "T_start")
        goal = as_transform(self.T_goal, "T_goal")
        set_ = object.__setattr__
        set_(self, "limits", limits)
        set_(self, "T_start", start)
        set_(self, "T_goal", goal)
        positive_fields(self, {"position_tolerance": "m", "angle_tolerance": "rad"})
        if self.q_start is None:
            q_start = solve_ik(robot, start).q
        else:
            q_start = as_vector(self.q_start, "q_start", robot.dof)
            limits.check_position(q_start, tolerance=1e-9, context="q_start")
            gap = float(np.linalg.norm(robot.tool_pose(q_start)[:3, 3] - start[:3, 3]))
            if gap > self.position_tolerance:
                raise InvalidInputError(
                    f"q_start puts the tool {gap:.3g} m from T_start (tolerance "
                    f"{self.position_tolerance:.3g} m)",
                    name="q_start",
                )
        set_(self, "q_start", q_start)
        solve_ik(robot, goal, q_near=q_start)  # raises UnreachableError for an unreachable goal
        if self.duration is not None:
            set_(self, "duration", as_duration(self.duration, "duration"))
        if self.speed is not None:
            set_(self, "speed", positive(self.speed, "speed", "m/s", maximum=MAX_TOOL_SPEED))

    @property
    def length(self) -> float:
        """Length of the line [m]."""
        return float(
            np.linalg.norm(np.asarray(self.T_goal)[:3, 3] - np.asarray(self.T_start)[:3, 3])
        )

    @property
    def still(self) -> bool:
        """Whether T_goal equals T_start: the tool moves and turns by at most STILL_TOLERANCE.

        The rule of :attr:`problems.PointToPoint.still`, in m for the position and rad for
        the rotation angle.
        """
        start, goal = np.asarray(self.T_start), np.asarray(self.T_goal)
        turn = start[:3, :3].T @ goal[:3, :3]
        # the angle from its sine and cosine: arccos alone turns round-off into 1e-8 rad
        sine = 0.5 * np.linalg.norm(
            [turn[2, 1] - turn[1, 2], turn[0, 2] - turn[2, 0], turn[1, 0] - turn[0, 1]]
        )
        angle = float(np.arctan2(sine, 0.5 * (np.trace(turn) - 1.0)))
        return self.length <= STILL_TOLERANCE and angle <= STILL_TOLERANCE

    def require_motion(self, planner: str) -> None:
        """Refuse, for ``planner``, a line that stays still and has no duration.

        Raises:
            InvalidInputError: Naming ``T_goal``, saying to give a duration to hold still.
        """
        if self.duration is None and self.still:
            raise still_error(
                planner,
                what="T_goal equals T_start",
                within="the tool moves and turns by at most",
                name="T_goal",
            )

    def constraints(self) -> tuple[Constraint, ...]:
        """Rest at the start configuration, on the line throughout, rest at the end."""
        n = self.limits.n
        return (
            BoundaryState("start", np.asarray(self.q_start), np.zeros(n)),
            ToolPath(
                np.asarray(self.T_start),
                np.asarray(self.T_goal),
                None,
                self.position_tolerance,
                self.angle_tolerance,
                self.speed,
            ),
            BoundaryState("end", None, np.zeros(n)),
        )
