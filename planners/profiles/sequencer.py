"""Sequences of moves: pick-and-place with classic profiles, seven phases per object.

By default every move is a rest-to-rest joint move. With ``vertical=True`` the gripper goes
down onto each block and the pile, and back up, on vertical straight lines
(:mod:`.pick_moves`), leaving a released block by an eighth phase per object (``retreat``),
and a problem with a scene is refused if the plan puts two shapes that may not touch into
each other.
"""

from __future__ import annotations

import time

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.base import JointProfile, stamp
from optraj.planners.profiles.pick_moves import line_profile, require_clear, vertical_line
from optraj.planners.profiles.time_scaling import Quintic
from optraj.planners.trajectory import Trajectory
from optraj.problems import PickAndPlace
from optraj.problems.pick_and_place import RETREAT
from optraj.problems.point_to_point import is_still

__all__ = ["PickAndPlacePlanner"]


class PickAndPlacePlanner:
    """Plan a :class:`problems.PickAndPlace` as a chain of rest-to-rest moves.

    For object k: to the interim pose, turn to above the object, descend onto it, grasp
    (dwell), back to the interim pose, turn to above the pile, descend and release (dwell).
    Each move is the profile's fastest within the limits; phases are named
    ``<phase>_<k>`` as in :data:`problems.pick_and_place.PHASES`.

    With ``vertical``, each descent and the lift after a grasp are straight vertical lines of
    the TCP (the Cartesian line time-scaled like ``profile``: cubic, LSPB, else quintic),
    and after each release the TCP rises straight back to where its descent started (phase
    ``retreat_<k>``), so that the fingers leave the block as they came. The interim pose is
    the problem's (chosen from its scene when it has one and ``q_interim`` was None).

    Args:
        profile: A joint profile (Cubic, Quintic, LSPB, ...); Quintic by default.
        vertical: Vertical approach and retreat lines, and the collision guard, as above.
    """

    def __init__(self, profile: JointProfile | None = None, *, vertical: bool = False) -> None:
        self.profile = profile if profile is not None else Quintic()
        if not isinstance(self.profile, JointProfile):
            raise InvalidInputError(
                f"profile must be a planners.JointProfile, got {type(self.profile).__name__}",
                name="profile",
            )
        if not isinstance(vertical, bool):
            raise InvalidInputError(f"vertical must be a bool, got {vertical!r}", name="vertical")
        self.vertical = vertical

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata."""
        lines = ", vertical lines" if self.vertical else ""
        return f"pick and place ({self.profile.name}{lines})"

    def plan(self, problem: PickAndPlace) -> Trajectory:
        """Plan every object in turn; the trajectory ends at rest after the last release.

        Raises:
            InfeasibleError: A move cannot be made within the limits.
            UnreachableError: A point of a vertical line cannot be reached.
            CollisionError: (``vertical``, with a scene) two shapes that may not touch
                overlap somewhere in the plan: the pair, the time and the phase.
        """
        if not isinstance(problem, PickAndPlace):
            raise InvalidInputError(
                f"PickAndPlacePlanner plans a problems.PickAndPlace, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        moves = _Moves(self, problem)
        phases = [item for k in range(problem.count) for item in moves.object(k)]
        traj = Trajectory.sequence(phases, joint_names=problem.limits.names)
        if self.vertical:
            require_clear(traj, problem)
        return stamp(traj, self.name, started)


class _Moves:
    """The moves of one plan, each from where the previous one ended."""

    def __init__(self, planner: PickAndPlacePlanner, problem: PickAndPlace) -> None:
        self.planner = planner
        self.problem = problem
        self.current = np.asarray(problem.q_start)

    def object(self, k: int) -> list[tuple[str, list[Trajectory]]]:
        """The named phases of object k (see :class:`PickAndPlacePlanner`)."""
        p = self.problem
        pick, place = np.asarray(p.picks)[k], p.place_point(k)
        interim = np.asarray(p.q_interim)
        if not self.planner.vertical:
            phases = [
                ("interim", self.move(interim)),
                ("turn_to_object", self.move(p.q_above_pick[k])),
                ("descend", self.move(p.q_pick[k])),
                ("grasp", self.dwell()),
                ("back_to_interim", self.move(interim)),
                ("turn_to_target", self.move(p.q_above_place[k])),
                ("release", self.move(p.q_place[k]) + self.dwell()),
            ]
            return [(f"{name}_{k}", parts) for name, parts in phases]
        lift = -float(p.clearance) * np.asarray(p.approach)
        phases = [
            ("interim", self.move(interim)),
            ("turn_to_object", self.move(p.q_above_pick[k])),
            ("descend", self.line(pick)),
            ("grasp", self.dwell()),
            ("back_to_interim", self.line(pick + lift) + self.move(interim)),
            ("turn_to_target", self.move(p.q_above_place[k])),
            ("release", self.line(place) + self.dwell()),
            (RETREAT, self.line(place + lift)),
        ]
        return [(f"{name}_{k}", parts) for name, parts in phases]

    def move(self, target: np.ndarray) -> list[Trajectory]:
        """A joint move to ``target`` (none if already there: it would last 0 s)."""
        if is_still(self.current, target):
            return []
        part = self.planner.profile.move(self.current, target, self.problem.limits)
        self.current = np.asarray(target)
        return [part]

    def line(self, point: np.ndarray) -> list[Trajectory]:
        """A straight line of the TCP to ``point`` [m], orientation held."""
        part = vertical_line(self.problem, self.current, point, line_profile(self.planner.profile))
        self.current = np.asarray(part.sample(part.duration).q)
        return [part]

    def dwell(self) -> list[Trajectory]:
        """Hold still for the problem's grasp time."""
        return [Trajectory.constant(self.current, float(self.problem.grasp_time))]
