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

Usage (a quick look at one seeded move)::

    python benchmarks/bare_ocp.py
"""

from __future__ import annotations

import time
from typing import NamedTuple

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError

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


def main() -> None:
    """Solve the first seeded Panda move of issue 35 and print it."""
    from optraj import robots

    limits = robots.load("panda").limits
    rng = np.random.default_rng(35)
    span = limits.upper - limits.lower
    q0 = limits.lower + span * rng.uniform(0.1, 0.9, limits.n)
    q1 = limits.lower + span * rng.uniform(0.1, 0.9, limits.n)
    bare = BareMinTime(limits.lower, limits.upper, limits.velocity, limits.acceleration)
    for _ in range(3):
        solution = bare.solve(q0, q1)
    bound = np.max(rest_to_rest_time(q1 - q0, limits.velocity, limits.acceleration))
    print(solution, f"duration / rest-to-rest bound = {solution.duration / bound:.4f}")


if __name__ == "__main__":
    main()
