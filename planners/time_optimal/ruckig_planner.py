"""Time-optimal jerk-limited joint motion with Ruckig, as exact optraj trajectories.

Ruckig (``pip install ruckig``; Berscheid & Kröger, "Jerk-limited real-time trajectory
generation with arbitrary target states", RSS 2021) computes, for every joint, the fastest
motion from any state (position, velocity, acceleration) to any reachable target state under
box velocity, acceleration and jerk limits, and then stretches the faster joints so that all
of them arrive together. Each joint's motion is a chain of constant-jerk phases, so it is
piecewise cubic in time, which is exactly what :class:`~planners.trajectory.Trajectory`
stores: :func:`native_to_trajectory` converts Ruckig's result without sampling.

This module offers :class:`Ruckig`, a planner for :class:`problems.PointToPoint` that, unlike
the classic time scalings, accepts moving start and target states (this is how a strike is
entered at speed), and re-exports the rest of the Ruckig family from the modules that hold it:

* :func:`state_to_state`, the same move as a plain function, and :func:`stop`, the fastest
  stop from a moving state, used to brake after a strike (:mod:`.ruckig_move`);
* :class:`OnlineRuckig`, one control tick at a time, for controllers (:mod:`.ruckig_online`);
* :func:`ruckig_input` and :func:`calculate`, Ruckig's input and its offline calculation
  (:mod:`.ruckig_calculation`); :func:`native_to_trajectory` (:mod:`.ruckig_conversion`);
  the limit checks of the finished polynomials (:mod:`.ruckig_limits`); and the checks of
  options and states, :data:`SYNCHRONIZATIONS` among them (:mod:`.ruckig_validation`).

Every limit and state comparison follows the checker's one round-off rule
(:func:`planners.checker.round_off`), so that a plan that :meth:`Ruckig.plan` returns passes
:func:`planners.checker.check`: on a long move a breakpoint is known only to about 1e-13 s, over
which a steep acceleration ramp moves by more than a relative 1e-9 of its limit.
"""

from __future__ import annotations

import time

import numpy as np
import ruckig
from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.base import JointProfile, rest_to_rest_inputs
from optraj.planners.checker import state_allowance
from optraj.planners.time_optimal.ruckig_calculation import calculate, ruckig_input
from optraj.planners.time_optimal.ruckig_conversion import native_to_trajectory
from optraj.planners.time_optimal.ruckig_move import move_between_states, state_to_state, stop
from optraj.planners.time_optimal.ruckig_online import OnlineRuckig
from optraj.planners.time_optimal.ruckig_validation import (
    SYNCHRONIZATIONS,
    check_state,
    checked_limits,
    longest_minimum_duration,
    state_or_zeros,
    synchronization_option,
)
from optraj.planners.trajectory import Trajectory
from optraj.problems import PointToPoint
from optraj.robots import JointLimits

__all__ = [
    "SYNCHRONIZATIONS",
    "OnlineRuckig",
    "Ruckig",
    "calculate",
    "check_state",
    "checked_limits",
    "native_to_trajectory",
    "ruckig_input",
    "state_or_zeros",
    "state_to_state",
    "stop",
]


class Ruckig(JointProfile):
    """Time-optimal jerk-limited moves, rest-to-rest or between moving states.

    Results are exact piecewise cubics, checked against every limit; their polynomials are
    built on first use (:meth:`Trajectory.deferred`), so planning costs little more than
    Ruckig itself.

    Args:
        synchronization: How the joints are coordinated, one of :data:`SYNCHRONIZATIONS`:
            ``time`` (default; all start and end together), ``phase`` (also on a straight
            joint-space line when possible), ``time_if_necessary`` or ``none``.
        minimum_duration: Shortest duration [s] of every move, or None.

    Raises:
        UnknownNameError: An unknown synchronisation.
        InvalidInputError: A minimum duration outside [1e-6, 86400] s.
    """

    name = "ruckig"

    def __init__(
        self, synchronization: str = "time", minimum_duration: float | None = None
    ) -> None:
        synchronization_option(synchronization)
        self.synchronization = synchronization
        self.minimum_duration = longest_minimum_duration(minimum_duration)

    def __repr__(self) -> str:
        return (
            f"Ruckig(synchronization={self.synchronization!r}, "
            f"minimum_duration={self.minimum_duration!r})"
        )

    def move(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> Trajectory:
        """One rest-to-rest move, as fast as the limits allow.

        Args:
            q_start: Start positions [rad or m], shape (n,).
            q_goal: Goal positions [rad or m], shape (n,).
            limits: Joint limits.
            duration: Shortest duration [s] (Ruckig stretches a faster move to it; a move
                that needs longer takes longer), or None.

        Returns:
            See :func:`state_to_state`.

        Raises:
            See :func:`state_to_state`.
        """
        limits = checked_limits(limits)
        still_rule = None if self.minimum_duration is not None else self.name
        start, goal, duration = rest_to_rest_inputs(q_start, q_goal, limits, duration, still_rule)
        return state_to_state(
            start,
            None,
            None,
            goal,
            None,
            None,
            limits,
            synchronization=self.synchronization,
            minimum_duration=longest_minimum_duration(duration, self.minimum_duration),
        )

    def plan(self, problem: PointToPoint) -> Trajectory:
        """Plan a :class:`problems.PointToPoint`, which may start and end moving.

        Unprescribed accelerations (None) are taken as zero; the problem's duration, if
        any, is a minimum duration. The problem has already checked its states' shapes and
        positions, so only what Ruckig needs beyond that is checked here.

        Raises:
            InvalidInputError: Not a PointToPoint.
            InfeasibleError: The target state is out of reach within the limits, or the
                move breaks a limit (see :func:`state_to_state`).
            SolverError: Ruckig fails, or it ends farther from the target state than the
                problem's tolerance allows as the checker judges it (Ruckig meets targets to
                about 1e-8; a smaller tolerance may not be met).

        A returned plan passes :func:`planners.checker.check` against the problem.
        """
        if not isinstance(problem, PointToPoint):
            raise InvalidInputError(
                f"{type(self).__name__} plans a problems.PointToPoint, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        if self.minimum_duration is None:  # with one, a still move is a hold
            problem.require_motion(self.name)
        started = time.perf_counter()
        limits = checked_limits(problem.limits)
        minimum = self.minimum_duration
        if problem.duration is not None:
            minimum = longest_minimum_duration(problem.duration, minimum)
        # PointToPoint stores its states as validated float arrays (velocities zero at rest).
        traj = move_between_states(
            limits,
            problem.q_start,
            problem.qd_start,
            problem.qdd_start,
            problem.q_goal,
            problem.qd_goal,
            problem.qdd_goal,
            started=started,
            synchronization=self.synchronization,
            minimum_duration=minimum,
            check_limits=True,
            joint_names=None,  # the limits' names
        )
        _check_end(traj.metadata["native"], problem, limits)
        return traj


def _check_end(native: ruckig.Trajectory, problem: PointToPoint, limits: JointLimits) -> None:
    """Raise SolverError when Ruckig misses the prescribed end state as the checker judges it.

    Ruckig meets a target state only to its own precision (about 1e-8 rad off the target
    position), so a problem with a tighter tolerance would fail the checker's
    ``end state``. The rule is the checker's (:func:`planners.checker.state_allowance`),
    with no allowance for the jerk at the end, so a move that passes here passes there.
    The start needs no check: Ruckig's first piece is the start state itself.
    """
    duration = float(native.duration)
    ends = native.at_time(duration)  # lists: seven joints cost less in Python than in NumPy
    wanted = (problem.q_goal, problem.qd_goal, problem.qdd_goal)
    tolerance = float(problem.tolerance)
    # Within the bare tolerance is within the rule's allowance (which adds round-off to it).
    if (
        _within(ends[0], problem.q_goal.tolist(), tolerance)
        and _within(ends[1], problem.qd_goal.tolist(), tolerance)
        and (problem.qdd_goal is None or _within(ends[2], problem.qdd_goal.tolist(), tolerance))
    ):
        return
    actual = tuple(np.array(x, dtype=float) for x in ends)  # position, velocity, acceleration
    allowed = state_allowance(
        wanted, (actual[1], actual[2], np.zeros(limits.n)), tolerance, limits, duration
    )
    for order, (target, bound) in enumerate(zip(wanted, allowed, strict=True)):
        if target is None or bound is None:
            continue
        miss = np.abs(actual[order] - target)
        j = int(np.argmax(miss - bound))
        if miss[j] > bound[j]:
            quantity = ("position", "velocity", "acceleration")[order]
            unit = limits.unit(quantity, j)
            raise SolverError(
                "ruckig",
                "target state missed",
                detail=f"the move ends with the {quantity} of joint {limits.names[j]!r} "
                f"{miss[j]:.3g} {unit} off its target {target[j]:.6g} {unit}, beyond the "
                f"problem's tolerance {tolerance:.3g} (Ruckig meets targets to about 1e-8); "
                "give a larger tolerance",
            )


def _within(got: list[float], target: list[float], tolerance: float) -> bool:
    """Whether every ``|got - target|`` is at most ``tolerance`` (a NaN is not).

    A loop over Python floats: for a few joints cheaper than NumPy calls or ``map`` chains.
    """
    for x, y in zip(got, target, strict=True):  # noqa: SIM110  # all() of a generator costs more
        if not abs(x - y) <= tolerance:
            return False
    return True
