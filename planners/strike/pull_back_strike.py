"""The Sawyer pool-cue exercise's shot: pull the cue back, then run the constant-velocity line.

Reproduced as the baseline the other planners are compared with: a cubic joint move from the
start to the line's entry pose, then :class:`planners.profiles.cartesian.LinearTrajectory` from the
entry to the exit point at the commanded speed, then holding still. The cue jumps from rest to
full speed at the entry and back to rest at the exit: the checker reports the unbounded
accelerations this needs.
"""

from __future__ import annotations

import time

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.base import stamp
from optraj.planners.profiles.cartesian import MAX_IK_SAMPLES, LinearTrajectory
from optraj.planners.profiles.time_scaling import Cubic
from optraj.planners.trajectory import Trajectory
from optraj.problems import PoolStrike
from optraj.problems.point_to_point import is_still
from optraj.robots import solve_ik
from optraj.validation import as_count, as_duration

__all__ = ["PullBackStrike"]


class PullBackStrike:
    """Plan a :class:`problems.PoolStrike` the way the Sawyer pool-cue exercise does.

    Args:
        pull_back_time: Duration of the pull-back move [s]; the shortest cubic within the
            velocity and acceleration limits when None.
        hold_time: How long to hold still after the line [s].
        samples: IK samples along the line, in [1, MAX_IK_SAMPLES].

    Raises:
        InvalidInputError: A time that is not a duration in [MIN_DURATION, MAX_DURATION] s,
            or a sample count that is not an integer in range.
    """

    name = "pull-back + line"

    def __init__(
        self, pull_back_time: float | None = None, hold_time: float = 0.2, samples: int = 100
    ) -> None:
        self.pull_back = Cubic(duration=pull_back_time)
        self.hold_time = as_duration(hold_time, "hold_time")
        self.samples = as_count(samples, "samples", 1, maximum=MAX_IK_SAMPLES)

    def plan(self, problem: PoolStrike) -> Trajectory:
        """Pull back to the entry pose, strike along the line, hold.

        Raises:
            UnreachableError: The entry pose or a pose on the line cannot be reached.
            InfeasibleError: A fixed pull-back time breaks a joint limit.
        """
        if not isinstance(problem, PoolStrike):
            raise InvalidInputError(
                f"PullBackStrike plans a problems.PoolStrike, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        robot, limits = problem.robot, problem.limits
        q_entry = solve_ik(
            robot, problem.entry_point, axis=problem.direction, q_near=problem.q_contact
        ).q
        # already at the entry pose (the goal equals the start): no pull-back move
        still = self.pull_back.duration is None and is_still(problem.q_start, q_entry)
        pull_back = [] if still else [self.pull_back.move(problem.q_start, q_entry, limits)]
        line = LinearTrajectory(
            problem.entry_point,
            problem.exit_point,
            float(problem.speed),
            robot.tool_pose(q_entry)[:3, :3],
        )
        strike = line.to_joints(robot, q_entry, samples=self.samples)
        q_exit = strike.sample(strike.duration).q
        hold = Trajectory.constant(q_exit, self.hold_time)
        traj = Trajectory.sequence(
            [("pull back", pull_back), ("strike", [strike]), ("stop", [hold])],
            joint_names=robot.joint_names,
        )
        return stamp(traj, self.name, started, q_entry=np.round(q_entry, 6).tolist())
