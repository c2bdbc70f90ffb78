"""The faces every planner shows: ``plan(problem) -> Trajectory``.

Joint-space time scalings (cubic, quintic, LSPB) are :class:`JointProfile` s: they make one
rest-to-rest move with every joint starting and stopping together (``move``), and from that
plan a :class:`problems.PointToPoint`. Sequencing planners (via points, pick-and-place) chain
their moves.

:class:`~planners.compiled_cache.CompiledCache`, the pickling rule of planners that keep
compiled solvers, lives in its own module and is re-exported here.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError
from optraj.planners.compiled_cache import CompiledCache
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PointToPoint
from optraj.problems.point_to_point import is_still, still_error
from optraj.robots import JointLimits
from optraj.validation import as_duration, as_vector

__all__ = ["CompiledCache", "JointProfile", "Planner", "rest_to_rest_inputs", "stamp"]


@runtime_checkable
class Planner(Protocol):
    """Anything with ``plan(problem) -> Trajectory``."""

    def plan(self, problem: Any) -> Trajectory:
        """Plan a trajectory for the problem."""
        ...


def stamp(trajectory: Trajectory, planner: str, started: float, **extra: Any) -> Trajectory:
    """Record how a trajectory was made in its metadata (planner, solve time [s], status)."""
    trajectory.metadata.update(
        {
            "planner": planner,
            "solve_time": time.perf_counter() - started,
            "status": "ok",
            **extra,
        }
    )
    return trajectory


class JointProfile(ABC):
    """A time scaling that moves all joints rest-to-rest, synchronised.

    Subclasses implement :meth:`move`; :meth:`plan` handles a :class:`problems.PointToPoint`
    that starts and ends at rest.
    """

    #: Short name recorded in trajectory metadata.
    name = "profile"

    @abstractmethod
    def move(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> Trajectory:
        """One rest-to-rest move; every joint starts and ends together.

        Args:
            q_start: Start positions [rad or m], shape (n,).
            q_goal: Goal positions [rad or m], shape (n,).
            limits: Limits to respect when ``duration`` is None (the fastest such move).
            duration: Fixed duration [s], or None.

        Returns:
            The move, with the joint names of ``limits`` and no phases.
        """

    def plan(self, problem: PointToPoint) -> Trajectory:
        """Plan a rest-to-rest :class:`problems.PointToPoint` move.

        Raises:
            InvalidInputError: The problem is not a PointToPoint, or it starts or ends moving
                (this profile plans rest-to-rest moves), or it prescribes an acceleration
                (which this profile does not meet), or its goal equals its start and it
                has no duration (:meth:`problems.PointToPoint.require_motion`).
        """
        if not isinstance(problem, PointToPoint):
            raise InvalidInputError(
                f"{type(self).__name__} plans a problems.PointToPoint, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        for label, values in (("qd_start", problem.qd_start), ("qd_goal", problem.qd_goal)):
            if values is not None and np.any(np.asarray(values) != 0.0):
                raise InvalidInputError(
                    f"{type(self).__name__} plans rest-to-rest moves; {label} = "
                    f"{np.round(np.asarray(values), 6).tolist()} is not zero",
                    name=label,
                )
        # its end accelerations follow from the timing (an LSPB starts at full acceleration)
        refuse_prescribed_accelerations(problem, type(self).__name__)
        problem.require_motion(self.name)
        started = time.perf_counter()
        traj = self.move(problem.q_start, problem.q_goal, problem.limits, problem.duration)
        traj = Trajectory(
            traj.breakpoints,
            traj.coefficients,
            joint_names=problem.limits.names,
            phases=[Phase("move", 0.0, traj.duration)],
            metadata=traj.metadata,
        )
        return stamp(traj, self.name, started)


def refuse_prescribed_accelerations(problem: PointToPoint, planner: str) -> None:
    """Refuse a problem that prescribes an end acceleration, for a profile that meets none.

    A profile whose end accelerations follow from its positions, velocities and timing
    meets no prescribed acceleration, not even zero.

    Raises:
        InvalidInputError: ``qdd_start`` or ``qdd_goal`` is given; names it and ``planner``.
    """
    for label in ("qdd_start", "qdd_goal"):
        if getattr(problem, label) is not None:
            raise InvalidInputError(
                f"{planner} cannot meet prescribed accelerations ({label} is given); leave it "
                "None or use Quintic",
                name=label,
            )


def rest_to_rest_inputs(
    q_start: ArrayLike,
    q_goal: ArrayLike,
    limits: JointLimits,
    duration: float | None,
    planner: str | None = None,
) -> tuple[np.ndarray, np.ndarray, float | None]:
    """Validate the arguments of :meth:`JointProfile.move`.

    Args:
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
        limits: The limits (their joint count n).
        duration: Fixed duration [s], or None.
        planner: When given, the name of a planner that refuses a move without a duration
            whose goal equals its start (the rule of
            :meth:`problems.PointToPoint.require_motion`); None leaves that to the caller.

    Returns:
        (q_start, q_goal, duration) as arrays of shape (n,) and a float in
        [MIN_DURATION, MAX_DURATION] s or None.

    Raises:
        InvalidInputError: Wrong shapes, non-finite values, a duration that is not a number
            in range, or (with ``planner``) a still move without a duration.
    """
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(
            f"limits must be a robots.JointLimits, got {type(limits).__name__}", name="limits"
        )
    start = as_vector(q_start, "q_start", limits.n)
    goal = as_vector(q_goal, "q_goal", limits.n)
    if duration is not None:
        duration = as_duration(duration, "duration")
    elif planner is not None and is_still(start, goal):
        raise still_error(planner)
    return start, goal, duration
