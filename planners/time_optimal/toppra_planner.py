r"""Time-optimal retiming of a geometric joint path with TOPPRA, as exact optraj trajectories.

TOPPRA (``pip install toppra``; Pham & Pham, "A new approach to time-optimal path
parameterization based on reachability analysis", IEEE T-RO 2018) takes a path
:math:`q(s)`, :math:`s \in [s_0, s_N]`, and constraints that are linear in the path
acceleration :math:`u = \ddot s` and the squared path velocity :math:`x = \dot s^2`,

.. math:: \dot q = q'(s)\,\dot s, \qquad \ddot q = q'(s)\,u + q''(s)\,x,

and finds the fastest :math:`\dot s` on a grid :math:`s_0 < s_1 < \dots < s_N` with small
linear programs, backwards (controllable sets) then forwards (greedy). :class:`Toppra` wraps
it with the ``plan(problem)`` face; ``toppra`` itself is imported on the first plan.

Paths
    :meth:`Toppra.plan` takes a :class:`problems.Waypoints` (a not-a-knot cubic spline through
    the waypoints, :math:`s` = cumulative chord length; a shape-preserving PCHIP cubic instead
    when the spline would leave the joint limits) or a :class:`problems.PointToPoint` (the
    straight joint-space line). :meth:`Toppra.time_parametrize` retimes an array of waypoints
    the same way, or any :class:`~planners.trajectory.Trajectory` used as a geometric path:
    its positions over its own time are the path (:math:`s` = its time) and its phases are
    carried over to the new times. :meth:`Toppra.build` sets up the problem without solving
    it, for inspection; :meth:`Toppra.solve` solves it.

Failures
    Typed errors, never ``None``: a path through a joint limit (:class:`JointLimitError`
    naming the joint and the path position), a torque limit that gravity alone breaks on the
    path, a start or end path velocity beyond what the limits allow (the requested and the
    largest feasible value), an empty controllable set (its grid index and path position)
    are :class:`InfeasibleError`; a failed forward pass is a :class:`SolverError`.

The pieces, each in its own module of :mod:`planners.time_optimal`:

* ``toppra_path``: the geometric path (spline, PCHIP, line, a trajectory's positions)
  and the lazy import of ``toppra_classes``;
* ``toppra_path_checks``: the path within the position limits and without corners;
* ``toppra_problem``: the built problem, :class:`ToppraProblem`, and :data:`MARGIN`;
* ``toppra_grid``: the gridpoints, their refinement, the stretched parameter of short paths;
* ``toppra_constraints``: velocity, acceleration, torque and tool speed constraints;
* ``toppra_classes``: the classes derived from toppra's (imported with toppra);
* ``toppra_solve``: the solves and their retries, and the trajectory they give;
* ``toppra_verify``: bounds on every limit between gridpoints;
* ``toppra_time_law``: toppra's answer as exact polynomials in time (:func:`compose`);
* ``toppra_failures``: the typed errors for what no timing can do.

Example::

    robot = robots.load("sawyer")
    problem = problems.Waypoints(robot, robot.random_configurations(4, rng))
    traj = Toppra().plan(problem)
    traj.metadata["native"]  # toppra's ParametrizeConstAccel output
"""

from __future__ import annotations

import math
import time

import numpy as np
from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError
from optraj.planners.time_optimal import toppra_solve
from optraj.planners.time_optimal.toppra_constraints import (
    X_CAP,
    chord_safe_bound,
    jump_rows,
    normalised_rows,
)
from optraj.planners.time_optimal.toppra_grid import grid_for
from optraj.planners.time_optimal.toppra_path import GeometricPath, curvature_jumps, segment_of
from optraj.planners.time_optimal.toppra_path_checks import (
    check_path_positions,
    check_tangent,
    waypoint_path,
)
from optraj.planners.time_optimal.toppra_problem import MARGIN, ToppraProblem
from optraj.planners.time_optimal.toppra_solve import RETRIES
from optraj.planners.time_optimal.toppra_time_law import compose
from optraj.planners.trajectory import Trajectory
from optraj.problems import PointToPoint, Waypoints
from optraj.problems.common import MAX_TOOL_SPEED
from optraj.problems.point_to_point import still_error
from optraj.robots import JointLimits, Robot
from optraj.validation import as_array, as_count, as_flag, as_number, as_positive

# The planner, and names of its pieces that other modules and tests import from here.
__all__ = [
    "MARGIN",
    "MAX_GRIDPOINTS",
    "RETRIES",
    "GeometricPath",
    "Toppra",
    "ToppraProblem",
    "chord_safe_bound",
    "compose",
    "curvature_jumps",
    "jump_rows",
    "normalised_rows",
]

#: Most grid intervals a planner may ask for: this many take seconds to solve, far fewer
#: (the default is at most 400) already resolve a path, and many more exhaust the memory.
MAX_GRIDPOINTS = 100_000


class Toppra:
    """Time-optimal path parametrisation with TOPPRA; the ``plan(problem)`` face.

    Args:
        gridpoints: Number of grid intervals N along the path (the grid holds N + 1
            gridpoints: toppra's N stages). By default one per 0.02 rad (or m) of
            joint-space path length, clipped to [100, 400]. Intervals are spread over the
            path's segments in proportion to their length, so every knot is a gridpoint (a
            path of more than N segments gets one interval per segment).
        torque: Also respect the joint torque limits (``limits.effort``), with inverse
            dynamics by the robot's RNEA; needs a robot.
        tool_speed: Cap on the speed of the tool frame origin [m/s], or None; needs a robot.
        start_path_velocity: Default path velocity at the start for
            :meth:`time_parametrize` [path units/s], >= 0.
        end_path_velocity: Default path velocity at the end for :meth:`time_parametrize`
            [path units/s], >= 0.

    Path units: a waypoint path is parametrised by cumulative chord length in joint space
    [rad or m] (a path velocity of 1 moves the joints at 1 rad/s along the chords), a
    Trajectory path by its own time [s] (a path velocity of 1 replays it at its own pace).

    Raises:
        InvalidInputError: A gridpoint count below 2 or above MAX_GRIDPOINTS, a tool speed
            <= 0 or above MAX_TOOL_SPEED, path velocities below 0 or above 1e8, a torque flag
            that is not a bool.
    """

    #: Name recorded in trajectory metadata.
    name = "toppra"

    def __init__(
        self,
        gridpoints: int | None = None,
        torque: bool = False,
        tool_speed: float | None = None,
        start_path_velocity: float = 0.0,
        end_path_velocity: float = 0.0,
    ) -> None:
        self.gridpoints = (
            None
            if gridpoints is None
            else as_count(gridpoints, "gridpoints", 2, maximum=MAX_GRIDPOINTS)
        )
        self.torque = as_flag(torque, "torque")
        self.tool_speed = (
            None
            if tool_speed is None
            else as_positive(tool_speed, "tool_speed", "m/s", maximum=MAX_TOOL_SPEED)
        )
        self.start_path_velocity = _path_velocity(start_path_velocity, "start_path_velocity")
        self.end_path_velocity = _path_velocity(end_path_velocity, "end_path_velocity")

    def __repr__(self) -> str:
        return (
            f"Toppra(gridpoints={self.gridpoints}, torque={self.torque}, "
            f"tool_speed={self.tool_speed}, start_path_velocity={self.start_path_velocity}, "
            f"end_path_velocity={self.end_path_velocity})"
        )

    # ---------------------------------------------------------------------- faces

    def plan(self, problem: Waypoints | PointToPoint) -> Trajectory:
        """Plan a problem time-optimally along a fixed geometric path.

        * :class:`problems.Waypoints`: a not-a-knot cubic spline through the waypoints
          (s = cumulative chord length), at rest at both ends, with phases ``segment 1`` ..
          ``segment k-1`` between the waypoints. Where that spline would leave the joint
          limits, a shape-preserving PCHIP cubic through the same waypoints is used
          (``metadata["path"]`` says which).
        * :class:`problems.PointToPoint`: the straight joint-space line, phase ``move``. A
          start or goal velocity along the line is honoured as a path velocity.

        Raises:
            InvalidInputError: Another problem type; fixed segment durations or a fixed
                duration (TOPPRA chooses the timing); a boundary velocity off the line, a
                prescribed non-zero boundary acceleration, a goal equal to the start; a
                planner built with non-zero default path velocities.
            InfeasibleError, SolverError: As for :meth:`solve`.
        """
        started = time.perf_counter()
        if isinstance(problem, Waypoints):
            built = self._build_waypoints(problem)
        elif isinstance(problem, PointToPoint):
            built = self._build_line(problem)
        else:
            raise InvalidInputError(
                f"Toppra plans a problems.Waypoints or a problems.PointToPoint, got "
                f"{type(problem).__name__}; retime other paths with time_parametrize",
                name="problem",
            )
        return toppra_solve.solve(built, self.name, started)

    def time_parametrize(
        self,
        path: ArrayLike | Trajectory,
        limits: JointLimits,
        *,
        robot: Robot | None = None,
        sd_start: float | None = None,
        sd_end: float | None = None,
    ) -> Trajectory:
        """Retime a geometric path as fast as the limits allow.

        Args:
            path: Waypoints [rad or m], shape (k, n), k >= 2 (the spline of :meth:`plan`,
                s = cumulative chord length [rad]), or a
                :class:`~planners.trajectory.Trajectory` whose positions over its own time
                are the path (s = its time [s]; its phases move to the new times).
            limits: Joint limits to respect; the path must stay within the position limits.
            robot: The robot; needed for torque limits or a tool speed cap.
            sd_start: Path velocity at the start [path units/s], >= 0; the planner's
                ``start_path_velocity`` when None.
            sd_end: Path velocity at the end [path units/s], >= 0; the planner's
                ``end_path_velocity`` when None.

        Returns:
            The retimed trajectory: exact piecewise polynomials (see :func:`compose`).

        Raises:
            InvalidInputError: A malformed path or limits, a path with a corner, a missing
                robot, a negative path velocity.
            JointLimitError: The path leaves the position limits (joint and s named).
            InfeasibleError, SolverError: As for :meth:`solve`.
        """
        started = time.perf_counter()
        built = self.build(path, limits, robot=robot, sd_start=sd_start, sd_end=sd_end)
        return toppra_solve.solve(built, self.name, started)

    def build(
        self,
        path: ArrayLike | Trajectory,
        limits: JointLimits,
        *,
        robot: Robot | None = None,
        sd_start: float | None = None,
        sd_end: float | None = None,
    ) -> ToppraProblem:
        """Validate a path and set up the problem that :meth:`solve` solves.

        Arguments and errors as for :meth:`time_parametrize` (which is ``solve(build(...))``).
        """
        if not isinstance(limits, JointLimits):
            raise InvalidInputError(
                f"limits must be a robots.JointLimits, got {type(limits).__name__}",
                name="limits",
            )
        start = (
            self.start_path_velocity if sd_start is None else _path_velocity(sd_start, "sd_start")
        )
        end = self.end_path_velocity if sd_end is None else _path_velocity(sd_end, "sd_end")
        if isinstance(path, Trajectory):
            if path.dof != limits.n:
                raise InvalidInputError(
                    f"the path has {path.dof} joints, the limits {limits.n}", name="path"
                )
            geometric = GeometricPath.from_trajectory(path)
            if not np.any(geometric.coefficients[:, 1:, :]):
                raise InvalidInputError(
                    "the path trajectory stands still: there is no path to parametrise",
                    name="path",
                )
            check_tangent(geometric, limits)
            check_path_positions(geometric, limits)
            phases = tuple((p.name, p.t_start, p.t_end) for p in path.phases)
            return self._assemble(geometric, limits, robot, start, end, phases)
        points = as_array(path, "path", (None, limits.n))
        if points.shape[0] < 2:
            raise InvalidInputError(
                f"path needs at least 2 waypoints, got {points.shape[0]}", name="path"
            )
        for k, q in enumerate(points):
            limits.check_position(q, tolerance=1e-9, context=f"path waypoint {k}")
        geometric, _ = waypoint_path(points, limits)
        return self._assemble(geometric, limits, robot, start, end, ())

    def solve(self, problem: ToppraProblem) -> Trajectory:
        """Solve a built problem.

        Raises:
            InfeasibleError: Gravity alone breaks a torque limit on the path (joint and s
                named); the start or end path velocity is beyond what the limits allow (the
                requested and the largest feasible value named); the controllable set is
                empty at a gridpoint (index and s named).
            SolverError: toppra's forward pass failed, or a motion with a moving start or
                end still exceeds a limit between gridpoints after the re-solves (more
                gridpoints help).
        """
        return toppra_solve.solve(problem, self.name, time.perf_counter())

    # ------------------------------------------------------------------ building

    def _build_waypoints(self, problem: Waypoints) -> ToppraProblem:
        self._require_rest("Waypoints")
        if problem.segment_durations is not None:
            raise InvalidInputError(
                "Toppra chooses the timing itself; a Waypoints problem with "
                "segment_durations cannot be honoured (leave them None, or use "
                "planners.ViaPoints)",
                name="segment_durations",
            )
        problem.require_motion(  # segment_durations are None here: Toppra cannot hold still
            self.name,
            reason="so there is no path to parametrise",
            remedy="give segment_durations to hold still and plan with planners.ViaPoints",
        )
        limits = _limits_of(problem)
        path, index = waypoint_path(np.asarray(problem.waypoints, dtype=float), limits)
        s = path.knots[index]
        phases = tuple((f"segment {k + 1}", s[k], s[k + 1]) for k in range(s.size - 1))
        return self._assemble(path, limits, problem.robot, 0.0, 0.0, phases)

    def _build_line(self, problem: PointToPoint) -> ToppraProblem:
        self._require_rest("PointToPoint")
        if problem.duration is not None:
            raise InvalidInputError(
                "Toppra plans the fastest motion; a PointToPoint with a fixed duration "
                "cannot be honoured (leave duration None, or use a time scaling)",
                name="duration",
            )
        for label, value in (("qdd_start", problem.qdd_start), ("qdd_goal", problem.qdd_goal)):
            if value is not None and np.any(np.asarray(value) != 0.0):
                raise InvalidInputError(
                    f"Toppra cannot prescribe boundary accelerations; {label} = "
                    f"{np.round(np.asarray(value), 6).tolist()} is not zero",
                    name=label,
                )
        # the rule of every planner, rest to rest; Toppra itself takes no duration
        problem.require_motion(
            self.name, "give a duration to hold still, and plan it with a time scaling"
        )
        if problem.still:  # with a boundary velocity: no straight line to move along
            raise still_error(
                self.name,
                reason="so there is no straight line to move along",
                remedy="plan it with Ruckig or a time scaling",
            )
        q0 = np.asarray(problem.q_start, dtype=float)
        q1 = np.asarray(problem.q_goal, dtype=float)
        length = float(np.linalg.norm(q1 - q0))
        direction = (q1 - q0) / length
        speeds = []
        for label, value in (("qd_start", problem.qd_start), ("qd_goal", problem.qd_goal)):
            qd = np.zeros(q0.size) if value is None else np.asarray(value, dtype=float)
            along = float(qd @ direction)
            off = float(np.linalg.norm(qd - along * direction))
            if along < 0.0 or off > 1e-9 * max(1.0, abs(along)):
                raise InvalidInputError(
                    f"Toppra moves along the straight line from q_start to q_goal; {label} = "
                    f"{np.round(qd, 6).tolist()} does not point forwards along it",
                    name=label,
                )
            speeds.append(along)
        path = GeometricPath.line(q0, q1)
        limits = _limits_of(problem)
        return self._assemble(
            path, limits, problem.robot, speeds[0], speeds[1], (("move", 0.0, length),)
        )

    def _require_rest(self, what: str) -> None:
        if self.start_path_velocity != 0.0 or self.end_path_velocity != 0.0:
            raise InvalidInputError(
                f"a {what} problem prescribes its own boundary velocities; the planner's "
                "start_path_velocity and end_path_velocity apply to time_parametrize only",
                name="start_path_velocity",
            )

    def _assemble(
        self,
        path: GeometricPath,
        limits: JointLimits,
        robot: Robot | None,
        sd_start: float,
        sd_end: float,
        phases: tuple[tuple[str, float, float], ...],
    ) -> ToppraProblem:
        if (self.torque or self.tool_speed is not None) and not isinstance(robot, Robot):
            wanted = "torque limits need" if self.torque else "a tool speed cap needs"
            raise InvalidInputError(
                f"{wanted} the robot: pass robot=robots.load(...)", name="robot"
            )
        if robot is not None and robot.dof != limits.n:
            raise InvalidInputError(
                f"robot {robot.name!r} has {robot.dof} joints, the limits {limits.n}",
                name="robot",
            )
        grid = grid_for(path, self.gridpoints)
        return ToppraProblem(
            path=path,
            limits=limits,
            grid=grid,
            sd_start=float(sd_start),
            sd_end=float(sd_end),
            robot=robot,
            torque=self.torque,
            tool_speed=self.tool_speed,
            phases=phases,
            segment=segment_of(path.knots, grid[:-1]),
        )


def _path_velocity(value: float, name: str) -> float:
    """A path velocity [path units/s] in [0, sqrt(X_CAP)].

    toppra moves forwards only, and no squared path velocity above :data:`X_CAP` is offered
    to it.
    """
    return as_number(value, name, "path units/s", minimum=0.0, maximum=math.sqrt(X_CAP))


def _limits_of(problem: Waypoints | PointToPoint) -> JointLimits:
    limits = problem.limits
    if not isinstance(limits, JointLimits):  # resolved by the problem; never None
        raise InvalidInputError("the problem has no joint limits", name="limits")
    return limits
