"""Pieces of a pick-and-place plan that knows its scene: vertical lines and a collision guard.

* :func:`vertical_line`: the tool carried on a straight line (orientation held) from where a
  configuration puts it to a point: the approach and retreat above each grasp and release,
  planned by :class:`~optraj.planners.profiles.cartesian.CartesianStraightLine`.
* :func:`line_profile`: the Cartesian line's time scaling matching a joint profile.
* :func:`require_clear`: the plan judged against the problem's scene by the checker's
  ``clearance`` finding; a plan in which two shapes that may not touch overlap is refused
  with a :class:`optraj.errors.CollisionError` naming the pair, the time and the phase.

Example::

    descent = vertical_line(problem, q_above, problem.picks[0], "quintic")
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from optraj.errors import CollisionError
from optraj.planners.base import JointProfile
from optraj.planners.checker import check
from optraj.planners.checker.clearance import clearance_pair
from optraj.planners.profiles.cartesian import CartesianStraightLine
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.time_scaling import Cubic
from optraj.planners.trajectory import Trajectory
from optraj.problems import CartesianLine, PickAndPlace

__all__ = ["GUARD_RATE", "line_profile", "require_clear", "vertical_line"]

#: Sampling rate of the plan's own collision guard [Hz]; the checker's bound between
#: samples (from the joint speeds) covers the instants in between.
GUARD_RATE = 100.0


def line_profile(profile: JointProfile) -> str:
    """The :class:`CartesianStraightLine` profile for a joint profile: cubic, LSPB or quintic."""
    if isinstance(profile, Cubic):
        return "cubic"
    if isinstance(profile, LSPB):
        return "lspb"
    return "quintic"


def vertical_line(
    problem: PickAndPlace, q_from: ArrayLike, point: ArrayLike, profile: str
) -> Trajectory:
    """The TCP from where ``q_from`` puts it straight to ``point``, its orientation held.

    Rest to rest, as fast as the problem's joint limits allow the ``profile`` time scaling.

    Args:
        problem: The pick-and-place problem (robot and limits).
        q_from: Start configuration [rad or m], shape (n,).
        point: End point of the TCP [m], world frame, shape (3,).
        profile: ``"cubic"``, ``"quintic"`` or ``"lspb"``.

    Raises:
        UnreachableError: A point of the line cannot be reached.
        PathJumpError: The joint solution jumps on the way.
    """
    robot = problem.robot
    q_start = np.asarray(q_from, dtype=float)
    T_start = robot.tool_pose(q_start)
    T_goal = T_start.copy()
    T_goal[:3, 3] = np.asarray(point, dtype=float)
    line = CartesianLine(robot, T_start, T_goal, q_start=q_start, limits=problem.limits)
    return CartesianStraightLine(profile).plan(line)


def require_clear(traj: Trajectory, problem: PickAndPlace, rate: float = GUARD_RATE) -> None:
    """Refuse a plan in which two shapes of the problem's scene that may not touch overlap.

    Nothing to do without a scene. A plan that keeps every pair apart but closer than the
    scene's margin is returned: the checker's ``clearance`` finding reports it.

    Raises:
        CollisionError: The overlapping pair, its depth, and when (time and phase).
    """
    if problem.scene is None:
        return
    finding = check(traj, problem, rate=rate, quantities=[])["clearance"]
    if finding.value >= 0.0 or finding.time is None:
        return
    first, second = clearance_pair(finding)
    phase = next((p.name for p in traj.phases if p.t_start <= finding.time <= p.t_end), "")
    raise CollisionError(
        first, second, finding.value, what=f"the plan at t = {finding.time:.4g} s ({phase})"
    )
