"""Sequences of joint moves: pick-and-place with classic profiles, seven phases per object."""

from __future__ import annotations

import time

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.base import JointProfile, stamp
from optraj.planners.profiles.time_scaling import Quintic
from optraj.planners.trajectory import Trajectory
from optraj.problems import PickAndPlace
from optraj.problems.point_to_point import is_still

__all__ = ["PickAndPlacePlanner"]


class PickAndPlacePlanner:
    """Plan a :class:`problems.PickAndPlace` as a chain of rest-to-rest joint moves.

    For object k: to the interim pose, turn to above the object, descend onto it, grasp
    (dwell), back to the interim pose, turn to above the pile, descend and release (dwell).
    Each move is the profile's fastest within the limits; phases are named
    ``<phase>_<k>`` as in :data:`problems.pick_and_place.PHASES`.

    Args:
        profile: A joint profile (Cubic, Quintic, LSPB, ...); Quintic by default.
    """

    def __init__(self, profile: JointProfile | None = None) -> None:
        self.profile = profile if profile is not None else Quintic()
        if not isinstance(self.profile, JointProfile):
            raise InvalidInputError(
                f"profile must be a planners.JointProfile, got {type(self.profile).__name__}",
                name="profile",
            )

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata."""
        return f"pick and place ({self.profile.name})"

    def plan(self, problem: PickAndPlace) -> Trajectory:
        """Plan every object in turn; the trajectory ends at rest after the last release.

        Raises:
            InfeasibleError: A move cannot be made within the limits.
        """
        if not isinstance(problem, PickAndPlace):
            raise InvalidInputError(
                f"PickAndPlacePlanner plans a problems.PickAndPlace, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        limits = problem.limits
        phases: list[tuple[str, list[Trajectory]]] = []
        current = np.asarray(problem.q_start)

        def add(name: str, parts: list[Trajectory]) -> None:
            phases.append((name, parts))

        def move(target: np.ndarray) -> list[Trajectory]:
            nonlocal current
            if is_still(current, target):  # already there: no move (it would last 0 s)
                return []
            part = self.profile.move(current, target, limits)
            current = np.asarray(target)
            return [part]

        def dwell() -> list[Trajectory]:
            return [Trajectory.constant(current, float(problem.grasp_time))]

        interim = np.asarray(problem.q_interim)
        for k in range(problem.count):
            add(f"interim_{k}", move(interim))
            add(f"turn_to_object_{k}", move(problem.q_above_pick[k]))
            add(f"descend_{k}", move(problem.q_pick[k]))
            add(f"grasp_{k}", dwell())
            add(f"back_to_interim_{k}", move(interim))
            add(f"turn_to_target_{k}", move(problem.q_above_place[k]))
            add(f"release_{k}", move(problem.q_place[k]) + dwell())
        traj = Trajectory.sequence(phases, joint_names=limits.names)
        return stamp(traj, self.name, started)
