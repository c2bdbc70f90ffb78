"""A joint-space move from one state to another."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.problems.common import (
    check_robot,
    checked_positions,
    checked_state,
    non_negative,
    resolve_limits,
)
from optraj.problems.constraints import BoundaryState, Constraint
from optraj.problems.scene import Scene
from optraj.robots import JointLimits, Robot
from optraj.validation import as_duration, as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["STILL_TOLERANCE", "PointToPoint", "is_still", "still_error"]

#: Largest displacement of any joint [rad or m] that counts as no move at all: a goal
#: within it of the start "equals the start". It sits far above the round-off of joint
#: positions (the spacing of doubles near the largest shipped limit, 2 pi, is 8.9e-16, and a
#: configuration that went through arithmetic carries a few such ulps) and far below any
#: joint's resolution (a 20-bit encoder resolves 2 pi / 2^20 = 6e-6 rad). It is not set by
#: a planner: the planners plan one-joint moves just above it that pass the checker
#: (tests/problems/test_point_to_point.py checks 2e-12 to 1e-9 on every robot).
STILL_TOLERANCE = 1e-12


def is_still(q_start: ArrayLike, q_goal: ArrayLike) -> bool:
    """Whether no joint moves more than :data:`STILL_TOLERANCE` from q_start to q_goal.

    Args:
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
    """
    start = np.asarray(q_start, dtype=float)
    goal = np.asarray(q_goal, dtype=float)
    if start.shape != goal.shape:  # broadcast, as NumPy does
        change = np.abs(goal - start)
        return float(np.max(change, initial=0.0)) <= STILL_TOLERANCE
    # Python floats: a few joints cost less this way than in NumPy calls (a NaN is not still).
    pairs = zip(start.ravel().tolist(), goal.ravel().tolist(), strict=True)
    return all(abs(b - a) <= STILL_TOLERANCE for a, b in pairs)


def still_error(
    planner: str,
    *,
    what: str = "q_goal equals q_start",
    within: str = "no joint moves more than",
    name: str = "q_goal",
    reason: str = "so the fastest move lasts 0 s",
    remedy: str = "give a duration to hold still",
) -> InvalidInputError:
    """The error for a move without a duration that stays still.

    Args:
        planner: Name of the refusing planner, for the message.
        what: What stays still, for the message.
        within: What the tolerance bounds, for the message.
        name: The argument named by the error.
        reason: Why that cannot be planned, for the message.
        remedy: What to do instead.
    """
    return InvalidInputError(
        f"{planner}: {what} ({within} {STILL_TOLERANCE:g} rad or m), {reason}: {remedy}",
        name=name,
    )


@dataclass(frozen=True, eq=False, init=False)  # __init__ below: one write of the fields
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
        scene: The robot's surroundings, or None: the goal must be clear of it, and the checker
            then reports the trajectory's ``clearance`` to it.

    A goal that equals the start (within :data:`STILL_TOLERANCE`) is a valid problem; a
    planner refuses it at planning time (:meth:`require_motion`) when it starts and ends at
    rest and has no duration, and plans a hold when it has one.
    """

    robot: Robot
    q_start: FloatArray
    q_goal: FloatArray
    qd_start: FloatArray = None  # type: ignore[assignment]  # None: rest (zeros)
    qd_goal: FloatArray = None  # type: ignore[assignment]  # None: rest (zeros)
    qdd_start: FloatArray | None = None
    qdd_goal: FloatArray | None = None
    duration: float | None = None
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__init__)
    tolerance: float = 1e-6
    scene: Scene | None = None

    def __init__(
        self,
        robot: Robot,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        qd_start: ArrayLike | None = None,
        qd_goal: ArrayLike | None = None,
        qdd_start: ArrayLike | None = None,
        qdd_goal: ArrayLike | None = None,
        duration: float | None = None,
        limits: JointLimits | None = None,
        tolerance: float = 1e-6,
        scene: Scene | None = None,
    ) -> None:
        """Check the states against the limits and store them as float arrays.

        Raises:
            JointLimitError: A position, velocity or acceleration beyond its limit.
            InvalidInputError: Not a robot, limits for other joints, wrong shapes,
                non-finite values, a duration outside [MIN_DURATION, MAX_DURATION] s, a
                negative tolerance, or a scene that is not a :class:`Scene`.
            CollisionError: With a scene, the goal configuration puts the robot inside it
                (the message names the pair).
        """
        limits = resolve_limits(check_robot(robot), limits)
        n = limits.n
        positions = checked_positions(limits, q_start, q_goal)
        if positions is None:  # the checks one by one, for the first error in this order
            # positions are required here (joint_state takes None for "not given")
            q0 = as_vector(q_start, "q_start", n)
            q1 = as_vector(q_goal, "q_goal", n)
            v0, a0 = checked_state(limits, q0, qd_start, qdd_start, "start")
            v1, a1 = checked_state(limits, q1, qd_goal, qdd_goal, "goal")
        else:  # both positions are within the limits
            q0, q1 = positions
            v0, a0 = checked_state(limits, None, qd_start, qdd_start, "start")
            v1, a1 = checked_state(limits, None, qd_goal, qdd_goal, "goal")
        if duration is not None:
            duration = as_duration(duration, "duration")
        # One write of the frozen fields rather than an object.__setattr__ call per field.
        vars(self).update(
            robot=robot,
            q_start=q0,
            q_goal=q1,
            qd_start=v0,
            qd_goal=v1,
            qdd_start=a0,
            qdd_goal=a1,
            duration=duration,
            limits=limits,
            tolerance=non_negative(tolerance, "tolerance", ""),
            scene=scene,
        )
        if scene is not None:
            _require_clear_goal(robot, scene, q1)

    @property
    def at_rest(self) -> bool:
        """Whether the move starts and ends at rest (zero velocities, no or zero accelerations)."""
        # Lists: a few floats are tested faster in Python than by NumPy (0.0 and -0.0 are
        # falsy, every other finite float truthy).
        for value in (self.qd_start, self.qd_goal, self.qdd_start, self.qdd_goal):
            if value is not None and any(value.tolist()):
                return False
        return True

    @property
    def still(self) -> bool:
        """Whether the goal equals the start: no joint moves more than STILL_TOLERANCE."""
        # The fields are validated arrays of one shape: is_still's test on their floats.
        for a, b in zip(self.q_start.tolist(), self.q_goal.tolist(), strict=True):
            if not abs(b - a) <= STILL_TOLERANCE:
                return False
        return True

    def require_motion(self, planner: str, remedy: str = "give a duration to hold still") -> None:
        """Refuse, for ``planner``, a rest-to-rest move that stays still and has no duration.

        The one rule every planner follows: the fastest such move lasts 0 s, which is no
        trajectory. With a duration, a planner that takes one plans a hold instead.

        Args:
            planner: Name of the planner, for the message.
            remedy: What to do instead, for the message (it should say to give a duration
                to hold still).

        Raises:
            InvalidInputError: Naming ``q_goal``; the message says "q_goal equals q_start"
                and to give a duration to hold still.
        """
        if self.duration is None and self.at_rest and self.still:
            raise still_error(planner, remedy=remedy)

    def constraints(self) -> tuple[Constraint, ...]:
        """Start and goal states."""
        return (
            BoundaryState("start", self.q_start, self.qd_start, self.qdd_start, self.tolerance),
            BoundaryState("end", self.q_goal, self.qd_goal, self.qdd_goal, self.tolerance),
        )


def _require_clear_goal(robot: Robot, scene: object, q_goal: FloatArray) -> None:
    """CollisionError naming the pair when ``q_goal`` puts ``robot`` inside ``scene``."""
    from optraj.problems.scene_distances import SceneCollision

    if not isinstance(scene, Scene):
        raise InvalidInputError(
            f"scene must be a problems.Scene or None, got {type(scene).__name__}", name="scene"
        )
    SceneCollision(robot, scene).require_clear(q_goal, "q_goal")
