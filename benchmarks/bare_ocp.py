"""A bare minimum-time rest-to-rest OCP in plain CasADi + IPOPT: the peer of issue 35.

The reference ``OptimalControl("time")`` is measured against (benchmarks/peers.py): what a
user would write by hand for the same move, with nothing of optraj in it.

Direct transcription on ``intervals`` intervals of equal length ``h = T / N``; the state is
position and velocity, the control a piecewise-constant acceleration (a double integrator,
so velocities are linear and positions quadratic within an interval); decisions are ``T``
[s], the node positions and velocities and the interval accelerations. Position, velocity
and acceleration limits are box bounds on the nodes (no jerk limit, positions checked at the
nodes only); the start and goal are NLP parameters, so one solver serves every move of the
same limits. The objective is ``T``.

First guess: ``T`` the slowest joint's own rest-to-rest minimum time under its velocity and
acceleration limits (a trapezoidal or triangular velocity profile, a lower bound of the
optimum), positions on the straight line, velocities and accelerations zero.

Usage (OptimalControl("time") and this OCP on issue 35's seeded Panda moves, interleaved:
time ratio, IPOPT iterations, motion time over the lower bound, first-plan ratios)::

    python benchmarks/bare_ocp.py [--moves 16] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import NamedTuple

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj import planners, problems, robots
from optraj.errors import InvalidInputError
from optraj.planners.time_optimal.lower_bound import lower_bound

FloatArray = NDArray[np.float64]


class BareSolution(NamedTuple):
    """One solve: motion time [s], IPOPT iterations, wall time of the solve [s], success."""

    duration: float
    iterations: int
    seconds: float
    success: bool


def rest_to_rest_time(
    distance: FloatArray, velocity: FloatArray, acceleration: FloatArray
) -> FloatArray:
    """Each joint's minimum rest-to-rest time [s] under velocity and acceleration limits.

    A triangular velocity profile when the cruise speed is not reached
    (``|d| <= v^2 / a``: ``2 sqrt(|d| / a)``), else a trapezoid (``|d| / v + v / a``).
    """
    d = np.abs(distance)
    triangle = 2.0 * np.sqrt(d / acceleration)
    trapezoid = d / velocity + velocity / acceleration
    return np.where(d <= velocity**2 / acceleration, triangle, trapezoid)


class BareMinTime:
    """Build the NLP once for these limits; solve() reuses it (parameters q0, q1).

    Args:
        lower, upper: Position limits [rad], shape (n,).
        velocity, acceleration: Symmetric velocity [rad/s] and acceleration [rad/s^2]
            limits, shape (n,).
        intervals: Transcription intervals ``N``.
    """

    def __init__(
        self,
        lower: ArrayLike,
        upper: ArrayLike,
        velocity: ArrayLike,
        acceleration: ArrayLike,
        intervals: int = 50,
    ) -> None:
        self.lower = np.asarray(lower, dtype=float)
        self.upper = np.asarray(upper, dtype=float)
        self.velocity = np.asarray(velocity, dtype=float)
        self.acceleration = np.asarray(acceleration, dtype=float)
        self.n = n = self.lower.size
        self.intervals = N = int(intervals)
        if N < 1:
            raise InvalidInputError(
                f"intervals must be >= 1, got {intervals}", name="intervals", value=intervals
            )

        T = ca.SX.sym("T")
        q = ca.SX.sym("q", n, N + 1)
        v = ca.SX.sym("v", n, N + 1)
        a = ca.SX.sym("a", n, N)
        p = ca.SX.sym("p", 2 * n)
        h = T / N

        rows = [q[:, 0] - p[:n], q[:, N] - p[n:]]
        for k in range(N):
            rows.append(q[:, k + 1] - (q[:, k] + h * v[:, k] + h**2 / 2 * a[:, k]))
            rows.append(v[:, k + 1] - (v[:, k] + h * a[:, k]))
        g = ca.vertcat(*rows)
        w = ca.vertcat(T, ca.vec(q), ca.vec(v), ca.vec(a))

        options = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes"}
        self._solver = ca.nlpsol(
            "bare_min_time", "ipopt", {"x": w, "f": T, "g": g, "p": p}, options
        )
        self._g_bound = np.zeros(g.shape[0])

        # Box bounds, in the order of w; the velocities at both ends are zero (rest to rest).
        v_low = np.tile(-self.velocity[:, None], (1, N + 1))
        v_high = np.tile(self.velocity[:, None], (1, N + 1))
        v_low[:, [0, N]] = 0.0
        v_high[:, [0, N]] = 0.0
        a_max = np.tile(self.acceleration[:, None], (1, N))
        self._lbw = np.concatenate(
            [
                [0.0],
                np.tile(self.lower[:, None], (1, N + 1)).ravel(order="F"),
                v_low.ravel(order="F"),
                (-a_max).ravel(order="F"),
            ]
        )
        self._ubw = np.concatenate(
            [
                [np.inf],
                np.tile(self.upper[:, None], (1, N + 1)).ravel(order="F"),
                v_high.ravel(order="F"),
                a_max.ravel(order="F"),
            ]
        )

    def guess(self, q0: FloatArray, q1: FloatArray) -> FloatArray:
        """First point: the slowest joint's own minimum time, a straight line, at rest."""
        N, n = self.intervals, self.n
        duration = float(np.max(rest_to_rest_time(q1 - q0, self.velocity, self.acceleration)))
        s = np.linspace(0.0, 1.0, N + 1)
        positions = q0[:, None] + (q1 - q0)[:, None] * s[None, :]
        zeros = np.zeros(n * (2 * N + 1))
        return np.concatenate([[max(duration, 1e-3)], positions.ravel(order="F"), zeros])

    def solve(self, q0: ArrayLike, q1: ArrayLike) -> BareSolution:
        """Minimum-time move from ``q0`` to ``q1`` at rest [rad], both shape (n,)."""
        start_q = np.asarray(q0, dtype=float)
        goal_q = np.asarray(q1, dtype=float)
        start = time.perf_counter()
        result = self._solver(
            x0=self.guess(start_q, goal_q),
            p=np.concatenate([start_q, goal_q]),
            lbx=self._lbw,
            ubx=self._ubw,
            lbg=self._g_bound,
            ubg=self._g_bound,
        )
        seconds = time.perf_counter() - start
        stats = self._solver.stats()
        return BareSolution(
            duration=float(result["x"][0]),
            iterations=int(stats["iter_count"]),
            seconds=seconds,
            success=bool(stats["success"]),
        )


def issue35_moves(count: int = 16) -> tuple[robots.Robot, FloatArray, FloatArray]:
    """The Panda and the seeded rest-to-rest moves of issue 35: (robot, starts, goals)."""
    robot = robots.load("panda")
    limits = robot.limits
    rng = np.random.default_rng(35)
    span = limits.upper - limits.lower
    starts = limits.lower + span * rng.uniform(0.1, 0.9, (count, limits.n))
    goals = limits.lower + span * rng.uniform(0.1, 0.9, (count, limits.n))
    return robot, starts, goals


def main() -> None:
    """OptimalControl("time") against BareMinTime on the same moves, interleaved; prints both."""
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=16, help="moves (issue 35: 16)")
    parser.add_argument("--repeats", type=int, default=5, help="timed plans per move")
    args = parser.parse_args()
    robot, starts, goals = issue35_moves(args.moves)
    limits = robot.limits
    moves = [problems.PointToPoint(robot, q0, q1) for q0, q1 in zip(starts, goals, strict=True)]
    bare = BareMinTime(limits.lower, limits.upper, limits.velocity, limits.acceleration)
    started = time.perf_counter()
    planners.OptimalControl("time").plan(moves[0])  # the process's first plan: NLP built
    first = time.perf_counter() - started
    planner = planners.OptimalControl("time")
    for move in moves:  # every grid's NLP built before timing
        planner.plan(move)
    ratios, iterations, bare_iterations, bounds, ok, reused, fresh = [], [], [], [], [], [], []
    for move, q0, q1 in zip(moves, starts, goals, strict=True):
        ours, theirs, new = [], [], []
        for _ in range(args.repeats):
            started = time.perf_counter()
            traj = planner.plan(move)
            ours.append(time.perf_counter() - started)
            theirs.append(bare.solve(q0, q1).seconds)
            started = time.perf_counter()
            planners.OptimalControl("time").plan(move)  # a new planner object
            new.append(time.perf_counter() - started)
        ratios.append(statistics.median(theirs) / statistics.median(ours))
        reused.append(statistics.median(ours))
        fresh.append(statistics.median(new) / statistics.median(ours))
        iterations.append(traj.metadata["iterations"])
        bare_iterations.append(bare.solve(q0, q1).iterations)
        bounds.append(traj.duration / lower_bound(move))
        ok.append(planners.check(traj, move).ok)
    print(f"moves {len(moves)}, repeats {args.repeats}, medians over moves")
    print(f"bare time / OptimalControl time: {statistics.median(ratios):.3f}")
    print(
        f"IPOPT iterations: OptimalControl {statistics.median(iterations):g}, "
        f"bare {statistics.median(bare_iterations):g}"
    )
    print(
        f"motion time / lower bound: median {statistics.median(bounds):.5f}, "
        f"mean {np.mean(bounds):.5f}, max {max(bounds):.5f}; checker passes {sum(ok)}/{len(ok)}"
    )
    print(f"new planner object / reused: {statistics.median(fresh):.3f}")
    print(f"process's first plan / reused: {first / statistics.median(reused):.2f}")


if __name__ == "__main__":
    main()
