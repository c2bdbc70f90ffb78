"""A pool shot: the cue tip runs along a line through the ball at a commanded speed."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.problems.common import (
    MAX_TOOL_SPEED,
    check_robot,
    joint_state,
    non_negative,
    positive,
    positive_fields,
    resolve_limits,
    unit_vector,
)
from optraj.problems.constraints import (
    STRIKE_ANGLE_TOLERANCE,
    STRIKE_POSITION_TOLERANCE,
    STRIKE_SPEED_TOLERANCE,
    BoundaryState,
    Constraint,
    StrikeLine,
)
from optraj.problems.scene import Scene
from optraj.problems.scene_distances import SceneCollision
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.validation import as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["MAX_WINDOW", "POOL_BALL_RADIUS", "PoolStrike"]

#: Radius of a pool ball [m] (standard diameter 57.15 mm, 2.25 in).
POOL_BALL_RADIUS = 0.028575

#: Longest strike window [s]: (run_up + follow_through) / speed. At the default distances a
#: minute is 2.5 mm/s; slower is a positioning move rather than a strike, and a window of
#: astronomical length (a speed near 0) turns the strike line's samples into NaNs.
MAX_WINDOW = 60.0


@dataclass(frozen=True, eq=False)
class PoolStrike:
    """Strike a ball with the cue tip: constant speed along a line, cue axis on the line.

    The tool (cue tip) starts at rest at ``q_start``, enters the strike line ``run_up``
    before the contact point, moves along it at ``speed`` with its z axis (the cue axis) along
    ``direction`` (roll free), meets the ball surface at ``ball - ball_radius * direction``,
    keeps going for ``follow_through``, then stops anywhere at rest.

    Attributes:
        robot: The robot; its tool frame is the cue tip (``robots.load("sawyer")``).
        ball: Ball centre [m], shape (3,).
        direction: Shot direction, shape (3,) (normalised here).
        speed: Cue tip speed during the strike [m/s]; the window it gives may last at most
            :data:`MAX_WINDOW`.
        run_up: Distance at constant speed before contact [m].
        follow_through: Distance at constant speed after contact [m].
        ball_radius: [m].
        q_start: Start configuration [rad]; the robot's home when None.
        limits: Limits to plan for; the robot's when None.
        position_tolerance: Allowed distance from the strike schedule [m].
        speed_tolerance: Allowed relative speed error [-].
        angle_tolerance: Allowed cue axis error [rad].
        scene: The surroundings (:class:`problems.Scene`, e.g. ``problems.pool_table(ball)``)
            or None (the default: no scene). With one, a cue in collision at contact is
            refused, the contact choice keeps the arm the scene's margin clear of it at
            contact, entry and exit, and ``planners.check`` adds its ``clearance`` finding.

    Derived: ``contact_point``, ``entry_point``, ``exit_point`` [m]; ``window`` (strike
    duration) and ``contact_delay`` [s]; ``q_contact``, an IK solution at contact near q_start
    [rad], found when the problem is built.
    """

    robot: Robot
    ball: FloatArray
    direction: FloatArray
    speed: float
    run_up: float = 0.10
    follow_through: float = 0.05
    ball_radius: float = POOL_BALL_RADIUS
    q_start: FloatArray = None  # type: ignore[assignment]  # None: resolved in __post_init__
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__post_init__)
    position_tolerance: float = STRIKE_POSITION_TOLERANCE
    speed_tolerance: float = STRIKE_SPEED_TOLERANCE
    angle_tolerance: float = STRIKE_ANGLE_TOLERANCE
    scene: Scene | None = None
    q_contact: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        """Validate the inputs and find the contact configuration.

        Raises:
            InvalidInputError: A bad field.
            UnreachableError: The strike line is out of reach.
            CollisionError: With a scene, the cue is in collision at contact.
        """
        robot = check_robot(self.robot)
        limits = resolve_limits(robot, self.limits)
        set_ = object.__setattr__
        set_(self, "limits", limits)
        ball = as_vector(self.ball, "ball", 3)
        direction = unit_vector(self.direction, "direction")
        speed = positive(self.speed, "speed", "m/s", maximum=MAX_TOOL_SPEED)
        # at most MAX_TOOL_SPEED * MAX_WINDOW each: a longer line lasts too long at any speed
        longest = MAX_TOOL_SPEED * MAX_WINDOW
        run_up = non_negative(self.run_up, "run_up", "m", maximum=longest)
        follow = non_negative(self.follow_through, "follow_through", "m", maximum=longest)
        if run_up + follow > longest:
            raise InvalidInputError(
                f"run_up + follow_through = {run_up + follow:.6g} m must be <= {longest:.6g} m: "
                f"at the fastest speed, {MAX_TOOL_SPEED:g} m/s, a longer strike window lasts "
                f"more than {MAX_WINDOW:g} s",
                name="run_up",
            )
        if run_up + follow <= 0.0:
            raise InvalidInputError(
                "run_up + follow_through must be > 0 m (the strike needs a window)",
                name="run_up",
            )
        # The slowest speed the message names, (run_up + follow_through) / MAX_WINDOW, must
        # pass itself: its window can come out a rounding above MAX_WINDOW.
        if (run_up + follow) / speed > MAX_WINDOW * (1.0 + 1e-12):
            raise InvalidInputError(
                f"speed {speed:.6g} m/s makes the strike window (run_up + follow_through = "
                f"{run_up + follow:.6g} m) last {(run_up + follow) / speed:.6g} s, more than "
                f"{MAX_WINDOW:g} s: the speed must be >= {(run_up + follow) / MAX_WINDOW:.6g} m/s",
                name="speed",
            )
        radius = non_negative(self.ball_radius, "ball_radius", "m")
        positive_fields(
            self,
            {"position_tolerance": "m", "speed_tolerance": "(relative)", "angle_tolerance": "rad"},
        )
        q_start, _, _ = joint_state(
            limits, robot.home if self.q_start is None else self.q_start, None, None, "start"
        )
        for name, value in (
            ("ball", ball),
            ("direction", direction),
            ("speed", speed),
            ("run_up", run_up),
            ("follow_through", follow),
            ("ball_radius", radius),
            ("q_start", q_start),
        ):
            set_(self, name, value)
        # Every point of the line must be reachable with the cue on it (UnreachableError if not).
        q_contact = solve_ik(robot, self.contact_point, axis=direction, q_near=q_start).q
        for end in (self.entry_point, self.exit_point):
            solve_ik(robot, end, axis=direction, q_near=q_contact)
        set_(self, "q_contact", q_contact)
        if self.scene is not None:
            # CollisionError if the cue is inside the scene at contact: the cue's place is
            # the same on every IK branch (up to a turn about its axis). The arm's is not:
            # the contact choice keeps the branches whose links clear the scene.
            SceneCollision(robot, self.scene).require_clear(
                q_contact, "the strike contact", shapes="tool/*"
            )

    @property
    def contact_point(self) -> np.ndarray:
        """Where the cue tip meets the ball surface [m], shape (3,)."""
        return np.asarray(self.ball) - float(self.ball_radius) * np.asarray(self.direction)

    @property
    def entry_point(self) -> np.ndarray:
        """Where the strike window starts [m], shape (3,)."""
        return self.contact_point - float(self.run_up) * np.asarray(self.direction)

    @property
    def exit_point(self) -> np.ndarray:
        """Where the strike window ends [m], shape (3,)."""
        return self.contact_point + float(self.follow_through) * np.asarray(self.direction)

    @property
    def window(self) -> float:
        """Length of the strike window [s]."""
        return (float(self.run_up) + float(self.follow_through)) / float(self.speed)

    @property
    def contact_delay(self) -> float:
        """Time from the window's start to contact [s]."""
        return float(self.run_up) / float(self.speed)

    def constraints(self) -> tuple[Constraint, ...]:
        """Rest at q_start, the strike line during phase ``strike``, rest at the end."""
        n = self.limits.n
        return (
            BoundaryState("start", np.asarray(self.q_start), np.zeros(n)),
            StrikeLine(
                phase="strike",
                point=self.contact_point,
                direction=np.asarray(self.direction),
                speed=float(self.speed),
                contact_delay=self.contact_delay,
                window=self.window,
                align_axis=True,
                position_tolerance=self.position_tolerance,
                speed_tolerance=self.speed_tolerance,
                angle_tolerance=self.angle_tolerance,
                run_up=float(self.run_up),
            ),
            BoundaryState("end", None, np.zeros(n)),
        )
