"""The paddle4 strike of the ECE486 paddle task: meet a ball with the paddle centre."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from optraj.problems.common import (
    MAX_TOOL_SPEED,
    check_robot,
    joint_state,
    non_negative,
    positive_fields,
    resolve_limits,
)
from optraj.problems.constraints import BoundaryState, Constraint, ToolContact
from optraj.robots import JointLimits, Robot, paddle4_ik
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import as_duration, as_number, as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["PaddleStrike"]

#: The ECE486 plan: reach the ball in T = 2 s, tabulated at f = 5 Hz.
ECE486_CONTACT_TIME = 2.0
ECE486_TABLE_RATE = 5.0


@dataclass(frozen=True, eq=False)
class PaddleStrike:
    """Bring the paddle centre to the ball at a given time, normal at the contact angle.

    With ``speed = 0`` (the ECE486 version) the paddle arrives at rest and the motion ends at
    contact. With ``speed > 0`` the ball centre is met at that speed along the paddle normal,
    and the motion continues until the robot stops.

    Attributes:
        robot: ``robots.load("paddle4")``.
        ball: Ball centre [m], shape (3,), inside the workspace cuboid.
        contact_angle: Angle of the paddle normal from +x about +z [rad].
        speed: Paddle speed along its normal at contact [m/s] (0: arrive at rest).
        contact_time: Time of contact after the start [s] (the ECE486 task's T = 2 s).
        q_start: Start configuration; the ECE486 home [0.45, 0, 0, 0] when None.
        limits: Limits to plan for; the robot's when None.
        position_tolerance: [m].
        angle_tolerance: [rad].
        velocity_tolerance: [m/s].

    Derived: ``q_contact``, the closed-form IK solution at contact [m, rad, m, rad];
    ``normal``, the paddle normal at contact, shape (3,).
    """

    robot: Robot
    ball: FloatArray
    contact_angle: float = 0.0
    speed: float = 0.0
    contact_time: float = ECE486_CONTACT_TIME
    q_start: FloatArray = None  # type: ignore[assignment]  # None: resolved in __post_init__
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__post_init__)
    position_tolerance: float = 1e-6
    angle_tolerance: float = 1e-6
    velocity_tolerance: float = 1e-6
    q_contact: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        robot = check_robot(self.robot, "paddle4")
        limits = resolve_limits(robot, self.limits)
        set_ = object.__setattr__
        set_(self, "limits", limits)
        set_(self, "ball", as_vector(self.ball, "ball", 3))
        set_(self, "contact_angle", as_number(self.contact_angle, "contact_angle", "rad"))
        set_(self, "speed", non_negative(self.speed, "speed", "m/s", maximum=MAX_TOOL_SPEED))
        set_(self, "contact_time", as_duration(self.contact_time, "contact_time"))
        positive_fields(
            self, {"position_tolerance": "m", "angle_tolerance": "rad", "velocity_tolerance": "m/s"}
        )
        q_start, _, _ = joint_state(
            limits, robot.home if self.q_start is None else self.q_start, None, None, "start"
        )
        set_(self, "q_start", q_start)
        set_(self, "q_contact", paddle4_ik(robot, self.ball, self.contact_angle))

    @property
    def normal(self) -> np.ndarray:
        """Paddle normal at contact, shape (3,)."""
        angle = float(self.contact_angle)
        return np.array([np.cos(angle), np.sin(angle), 0.0])

    def constraints(self) -> tuple[Constraint, ...]:
        """Rest at q_start; the paddle on the ball at contact_time; rest at the end."""
        n = self.limits.n
        contact = ToolContact(
            position=np.asarray(self.ball),
            axis=self.normal,
            velocity=float(self.speed) * self.normal,
            time=float(self.contact_time),
            offset=BALL_OFFSET,
            label="ball contact",
            position_tolerance=self.position_tolerance,
            angle_tolerance=self.angle_tolerance,
            velocity_tolerance=self.velocity_tolerance,
        )
        end_q = np.asarray(self.q_contact) if float(self.speed) == 0.0 else None
        return (
            BoundaryState("start", np.asarray(self.q_start), np.zeros(n)),
            contact,
            BoundaryState("end", end_q, np.zeros(n)),
        )
