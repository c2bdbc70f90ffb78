"""A joint-space move from one state to another."""

from __future__ import annotations

from dataclasses import dataclass

from numpy.typing import ArrayLike

from problems.common import check_robot, joint_state, non_negative, positive, resolve_limits
from problems.constraints import BoundaryState, Constraint
from robots import JointLimits, Robot

__all__ = ["PointToPoint"]


@dataclass(frozen=True, eq=False)
class PointToPoint:
    """Move the joints from a start state to a goal state.

    Velocities default to rest; accelerations are prescribed only when given.

    Attributes:
        robot: The robot.
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
        qd_start: Start velocities [rad/s or m/s], shape (n,); rest when None.
        qd_goal: Goal velocities [rad/s or m/s], shape (n,); rest when None.
        qdd_start: Start accelerations [rad/s^2 or m/s^2], shape (n,), or None (free).
        qdd_goal: Goal accelerations [rad/s^2 or m/s^2], shape (n,), or None (free).
        duration: Fixed duration [s], or None for as fast as the limits allow.
        limits: Limits to plan for; the robot's when None.
        tolerance: Allowed boundary-state deviation for the checker.
    """

    robot: Robot
    q_start: ArrayLike
    q_goal: ArrayLike
    qd_start: ArrayLike | None = None
    qd_goal: ArrayLike | None = None
    qdd_start: ArrayLike | None = None
    qdd_goal: ArrayLike | None = None
    duration: float | None = None
    limits: JointLimits | None = None
    tolerance: float = 1e-6

    def __post_init__(self) -> None:
        limits = resolve_limits(check_robot(self.robot), self.limits)
        set_ = object.__setattr__
        set_(self, "limits", limits)
        q0, v0, a0 = joint_state(limits, self.q_start, self.qd_start, self.qdd_start, "start")
        q1, v1, a1 = joint_state(limits, self.q_goal, self.qd_goal, self.qdd_goal, "goal")
        for name, value in (
            ("q_start", q0),
            ("qd_start", v0),
            ("qdd_start", a0),
            ("q_goal", q1),
            ("qd_goal", v1),
            ("qdd_goal", a1),
        ):
            set_(self, name, value)
        if self.duration is not None:
            set_(self, "duration", positive(self.duration, "duration", "s"))
        set_(self, "tolerance", non_negative(self.tolerance, "tolerance", ""))

    def constraints(self) -> tuple[Constraint, ...]:
        """Start and goal states."""
        return (
            BoundaryState("start", self.q_start, self.qd_start, self.qdd_start, self.tolerance),
            BoundaryState("end", self.q_goal, self.qd_goal, self.qdd_goal, self.tolerance),
        )
