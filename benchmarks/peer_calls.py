"""The peers of ``peers.py``, called the way their own users call them.

Robotics Toolbox (``jtraj``, ``mtraj`` with ``trapezoidal``, ``mstraj``), ruckig and toppra
called directly, Drake's ``KinematicTrajectoryOptimization`` with IPOPT, the bare CasADi
minimum-time OCP of ``bare_ocp.py``, and pink's ``solve_ik`` with daqp. Each peer is
imported on first use, so that a missing one costs only its own rows: :func:`missing`
says which of a peer's modules cannot be imported.
"""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from typing import Any

import numpy as np

from optraj import controllers, robots
from optraj.planners.time_optimal.lower_bound import lower_bound_va

#: Modules each peer needs, by peer name.
MODULES = {
    "Robotics Toolbox": ("roboticstoolbox",),
    "ruckig": ("ruckig",),
    "toppra": ("toppra",),
    "Drake": ("pydrake",),
    "bare CasADi OCP": ("bare_ocp",),
    "pink + daqp": ("pink", "daqp"),
}
#: Samples of the Robotics Toolbox trajectories (the protocol's ``np.linspace(0, T, 101)``).
SAMPLES = 101
#: mstraj's sample period [s] and acceleration time at each via point [s] (the protocol's).
MSTRAJ_DT = 0.01
MSTRAJ_TACC = 0.2
#: B-spline control points of Drake's problem: the count of the kinematic trajectory
#: optimization example in R. Tedrake's "Robotic Manipulation" notes (cubic B-spline).
DRAKE_CONTROL_POINTS = 10
#: Control period of the DiffIKQP task [s] (benchmarks/tracking.py's).
DT = 1e-3


class PeerError(RuntimeError):
    """A peer reported a failure on a move (its own status, not an exception of ours)."""


def missing(peer: str) -> str | None:
    """Why the peer cannot run: the first of its modules that cannot be imported, or None."""
    for module in MODULES[peer]:
        try:
            found = importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):
            found = False
        if not found:
            return (
                "benchmarks/bare_ocp.py missing"
                if module == "bare_ocp"
                else (f"{module} not installed")
            )
    return None


def _rtb() -> Any:
    return importlib.import_module("roboticstoolbox")


def jtraj(q0: Any, q1: Any, duration: float, qd0: Any, qd1: Any) -> Any:
    """Robotics Toolbox's quintic from (q0, qd0) to (q1, qd1) in ``duration`` [s]."""
    return _rtb().jtraj(q0, q1, np.linspace(0.0, duration, SAMPLES), qd0, qd1)


def trapezoidal(q0: Any, q1: Any, duration: float) -> Any:
    """Robotics Toolbox's multi-joint trapezoidal profile from q0 to q1 in ``duration`` [s]."""
    rtb = _rtb()
    return rtb.mtraj(rtb.trapezoidal, q0, q1, np.linspace(0.0, duration, SAMPLES))


def mstraj(points: Any, velocity: Any) -> Any:
    """Robotics Toolbox's multi-segment trajectory through ``points`` (k, n), start first."""
    return _rtb().mstraj(points, dt=MSTRAJ_DT, tacc=MSTRAJ_TACC, qdmax=velocity)


def ruckig_move(q0: Any, q1: Any, qd0: Any, qd1: Any, limits: robots.JointLimits) -> float:
    """ruckig's time-optimal move, its ``InputParameter`` built from the arrays; duration [s].

    Raises:
        PeerError: ruckig's result is an error.
    """
    import ruckig

    n = limits.n
    inp = ruckig.InputParameter(n)
    inp.current_position = q0
    inp.current_velocity = qd0
    inp.target_position = q1
    inp.target_velocity = qd1
    inp.max_velocity = limits.velocity
    inp.max_acceleration = limits.acceleration
    inp.max_jerk = limits.jerk
    out = ruckig.Trajectory(n)
    result = ruckig.Ruckig(n).calculate(inp, out)
    if result not in (ruckig.Result.Working, ruckig.Result.Finished):
        raise PeerError(f"ruckig: {result}")
    return float(out.duration)


def toppra_path(
    knots: Any, waypoints: Any, grid: Any, limits: robots.JointLimits, *, pchip: bool = False
) -> Callable[[], Any]:
    """toppra on a cubic through ``waypoints`` at path positions ``knots``, on ``grid``.

    The cubic is toppra's own ``SplineInterpolator`` (scipy's not-a-knot ``CubicSpline``), or
    with ``pchip`` scipy's ``PchipInterpolator`` behind toppra's path interface (what optraj
    takes where the spline would leave the position limits). Returns the call that
    parametrises the path with joint velocity and acceleration constraints, at rest at both
    ends; it raises :class:`PeerError` when toppra finds no parametrisation.
    """
    import toppra
    import toppra.algorithm
    import toppra.constraint

    def solve() -> Any:
        if pchip:
            path = _pchip_path(knots, waypoints)
        else:
            path = toppra.SplineInterpolator(knots, waypoints)
        velocity = toppra.constraint.JointVelocityConstraint(
            np.column_stack([-limits.velocity, limits.velocity])
        )
        acceleration = toppra.constraint.JointAccelerationConstraint(
            np.column_stack([-limits.acceleration, limits.acceleration])
        )
        instance = toppra.algorithm.TOPPRA(
            [velocity, acceleration], path, gridpoints=grid, parametrizer="ParametrizeConstAccel"
        )
        trajectory = instance.compute_trajectory(0.0, 0.0)
        if trajectory is None:
            raise PeerError("toppra: no parametrisation")
        return trajectory

    return solve


def _pchip_path(knots: Any, waypoints: Any) -> Any:
    """scipy's PCHIP through the waypoints as a toppra geometric path."""
    from scipy.interpolate import PchipInterpolator
    from toppra.interpolator import AbstractGeometricPath

    class PchipPath(AbstractGeometricPath):  # type: ignore[misc]
        """Positions and their first two derivatives along s, as toppra asks for them."""

        def __init__(self) -> None:
            self.knots = np.asarray(knots, dtype=float)
            self.points = np.asarray(waypoints, dtype=float)
            first = PchipInterpolator(self.knots, self.points)
            self.orders = (first, first.derivative(), first.derivative(2))

        def __call__(self, path_positions: Any, order: int = 0) -> Any:
            return self.orders[order](path_positions)

        @property
        def dof(self) -> int:
            return int(self.points.shape[1])

        @property
        def path_interval(self) -> Any:
            return np.array([self.knots[0], self.knots[-1]])

        @property
        def waypoints(self) -> Any:
            return self.knots, self.points

    return PchipPath()


class DrakeMinTime:
    """Drake's ``KinematicTrajectoryOptimization`` for rest-to-rest minimum time, with IPOPT.

    Joint space only: position, velocity and acceleration bounds (no jerk), a duration cost,
    the start and goal as path constraints whose bounds each move updates, so one program
    serves every move. First guess: the straight line, lasting the slowest joint's own
    minimum time (as ``bare_ocp.py``'s).
    """

    def __init__(self, limits: robots.JointLimits) -> None:
        from pydrake.planning import KinematicTrajectoryOptimization
        from pydrake.solvers import IpoptSolver

        n = limits.n
        self.limits = limits
        self.solver = IpoptSolver()
        kto = KinematicTrajectoryOptimization(n, DRAKE_CONTROL_POINTS, 4, 1.0)
        kto.AddDurationCost(1.0)
        kto.AddPositionBounds(limits.lower, limits.upper)
        kto.AddVelocityBounds(-limits.velocity, limits.velocity)
        kto.AddAccelerationBounds(-limits.acceleration, limits.acceleration)
        still = np.zeros(n)
        kto.AddPathVelocityConstraint(still, still, 0.0)
        kto.AddPathVelocityConstraint(still, still, 1.0)
        self.start = kto.AddPathPositionConstraint(limits.lower, limits.upper, 0.0)
        self.goal = kto.AddPathPositionConstraint(limits.lower, limits.upper, 1.0)
        self.kto = kto

    def solve(self, q0: Any, q1: Any) -> float:
        """The motion time [s] from q0 to q1 at rest.

        Raises:
            PeerError: IPOPT did not succeed.
        """
        kto, prog = self.kto, self.kto.get_mutable_prog()
        for binding, q in ((self.start, q0), (self.goal, q1)):
            binding.evaluator().UpdateLowerBound(q)
            binding.evaluator().UpdateUpperBound(q)
        line = np.linspace(q0, q1, DRAKE_CONTROL_POINTS).T
        prog.SetInitialGuess(kto.control_points(), line)
        guess = lower_bound_va(np.asarray(q1) - q0, self.limits.velocity, self.limits.acceleration)
        prog.SetInitialGuess(kto.duration(), guess)
        result = self.solver.Solve(prog)
        if not result.is_success():
            raise PeerError(f"Drake/IPOPT: {result.get_solution_result()}")
        return float(result.GetSolution(kto.duration()))


def bare_ocp(limits: robots.JointLimits) -> Any:
    """``bare_ocp.BareMinTime`` for the limits (its NLP built once, reused by every move)."""
    module = importlib.import_module("bare_ocp")
    return module.BareMinTime(limits.lower, limits.upper, limits.velocity, limits.acceleration)


def pink_daqp(robot: robots.Robot) -> Callable[[controllers.State, controllers.Reference], Any]:
    """One call of pink's ``solve_ik`` with daqp on benchmarks/tracking.py's task."""
    step = importlib.import_module("tracking").pink_stepper(robot, solver="daqp")
    if step is None:
        raise PeerError("pink is not installed")
    return step
