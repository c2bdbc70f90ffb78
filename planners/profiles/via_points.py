"""Joint trajectories through via points: multi-segment LSPB, or quintics through each point.

:class:`ViaPoints` plans a :class:`problems.Waypoints` problem, starting and ending at rest,
with one of two profiles:

``"lspb"`` (:mod:`optraj.planners.profiles.via_lspb`)
    Straight joint-space lines between the via points at constant velocity, joined by
    parabolic blends centred on each inner via point (Craig's "linear function with parabolic
    blends", Corke's ``mstraj``). The path cuts the inner via points by ``(v2 - v1) tb / 8``
    per joint; it starts and ends at rest on the waypoints exactly, and stays within the
    range of the waypoints.

``"quintic"`` (:mod:`optraj.planners.profiles.via_quintic`)
    One quintic per segment, through every via point exactly, with Craig's via velocities
    limited so that each segment is monotone, and zero via accelerations: C2, and never
    outside the range of its waypoints (so within the position limits).

Segment durations come from the problem (and are checked against the limits), or from the
limits: as short as the limits allow, found as each profile's module describes.

>>> from optraj import planners, problems, robots
>>> robot = robots.load("paddle4")
>>> problem = problems.Waypoints(robot, [[0.2, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0]])
>>> planners.ViaPoints("quintic").plan(problem).degree
5
"""

from __future__ import annotations

import time

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.base import stamp
from optraj.planners.profiles.via_lspb import plan_lspb
from optraj.planners.profiles.via_quintic import plan_quintic
from optraj.planners.trajectory import Trajectory
from optraj.problems import Waypoints
from optraj.robots import JointLimits
from optraj.validation import as_choice, as_duration

__all__ = ["PROFILES", "ViaPoints"]

#: Profile names accepted by :class:`ViaPoints`.
PROFILES: tuple[str, ...] = ("lspb", "quintic")


class ViaPoints:
    """Plan a :class:`problems.Waypoints` problem: through via points, from rest to rest.

    Args:
        profile: ``"lspb"`` (lines with parabolic blends; cuts the inner via points) or
            ``"quintic"`` (one C2 quintic per segment; passes every via point exactly).
        blend_time: For ``"lspb"``: one blend duration [s], > 0, for every blend; None for the
            shortest blend whose acceleration fits the limits at each via point.

    Raises:
        UnknownNameError: Unknown profile; lists the valid ones.
        InvalidInputError: blend_time <= 0, non-finite, or given for ``"quintic"``.
    """

    #: Name recorded in trajectory metadata.
    name = "via_points"

    def __init__(self, profile: str = "lspb", blend_time: float | None = None) -> None:
        as_choice(profile, "via-point profile", PROFILES)
        self.profile = profile
        self.blend_time: float | None = None
        if blend_time is not None:
            if profile != "lspb":
                raise InvalidInputError(
                    f"blend_time applies to profile 'lspb' only, not {profile!r}",
                    name="blend_time",
                )
            self.blend_time = as_duration(blend_time, "blend_time")

    def __repr__(self) -> str:
        blend = "" if self.blend_time is None else f", blend_time={self.blend_time!r}"
        return f"ViaPoints(profile={self.profile!r}{blend})"

    def plan(self, problem: Waypoints) -> Trajectory:
        """Plan the move through the problem's waypoints.

        Args:
            problem: The waypoints (k, n), optional segment durations (k - 1,) [s], optional
                via tolerance [rad or m], and the limits.

        Returns:
            A trajectory (degree 2 for ``"lspb"``, 5 for ``"quintic"``) from rest at the first
            waypoint to rest at the last, with phases ``segment 1`` ... ``segment k-1``
            between the via times. Metadata: ``profile``, ``segment_durations`` [s] (k - 1,),
            ``via_times`` [s] (k,), and per profile: ``blend_times`` [s] (k,),
            ``segment_velocities`` (k - 1, n), ``blend_accelerations`` (k, n),
            ``via_deviation`` (k - 2, n) [rad or m] (position minus via point at the via
            time) and ``max_via_deviation`` (lspb); ``via_velocities`` and
            ``via_accelerations`` (k, n) (quintic).

        Raises:
            InvalidInputError: Not a Waypoints problem, or every waypoint equal without
                segment durations (the move would last 0 s).
            InfeasibleError: Given segment durations break a velocity or acceleration limit
                (or the blends do not fit, or the lspb corner cut exceeds via_tolerance), or the
                quintic leaves the position limits; names the joint, the segment or
                via point, the required value and the limit.
        """
        if not isinstance(problem, Waypoints):
            raise InvalidInputError(
                f"ViaPoints plans a problems.Waypoints, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        limits = problem.limits
        if not isinstance(limits, JointLimits):  # set by Waypoints itself; kept for typing
            raise InvalidInputError("the problem has no joint limits", name="limits")
        points = np.asarray(problem.waypoints, dtype=float)
        given = problem.segment_durations
        durations = None if given is None else np.asarray(given, dtype=float)
        problem.require_motion(self.name)  # every waypoint the same, and no durations
        tolerance = problem.via_tolerance
        via_tolerance = None if tolerance is None else float(tolerance)
        if self.profile == "lspb":
            traj = plan_lspb(points, durations, limits, self.blend_time, via_tolerance)
        else:
            traj = plan_quintic(points, durations, limits)
        traj.metadata["durations_from"] = "limits" if durations is None else "problem"
        return stamp(traj, self.name, started, profile=self.profile)
