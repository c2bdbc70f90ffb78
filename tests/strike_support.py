"""References of the strike tests: the twist ratio's LP solved independently, pool shots.

The LP optimum by enumerating every vertex of the LP (numpy) and by scipy's linprog on the full
formulation (joint velocities as variables, task rows as equalities); the task rows rebuilt
from the Jacobian (and, for the paddle's ball point, by finite differences of its position);
the window ratio and the room-to-turn estimate of a pool contact from IK'd window ends.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.linalg import null_space
from scipy.optimize import linprog

from optraj import problems
from optraj.errors import UnreachableError
from optraj.planners.strike.twist_ratio import twist_ratio
from optraj.robots import solve_ik
from optraj.robots.paddle_ik import BALL_OFFSET


def reference_rows(robot, q, direction, align_axis=True):
    """Task rows rebuilt from the Jacobian: tool-origin velocity; angular velocity across d."""
    jac = robot.jacobian(q)
    across = null_space(direction[None, :]).T  # (2, 3), orthonormal, perpendicular to d
    rows = [jac[:3]] + ([across @ jac[3:]] if align_axis else [])
    target = np.concatenate([direction] + ([np.zeros(2)] if align_axis else []))
    return np.vstack(rows), target


def by_vertices(rows, target, vmax):
    """min over rows @ qd = target of max |qd_i| / vmax_i, by enumerating the LP's vertices.

    In y = qd / vmax = y0 + N z the feasible set {(z, s): |y0 + N z| <= s} has no lines
    (N has full column rank), so the optimum is at a vertex: k + 1 active constraints.
    """
    scaled = rows * vmax
    y0 = np.linalg.lstsq(scaled, target, rcond=None)[0]
    null = null_space(scaled)
    k = null.shape[1]
    if k == 0:
        return float(np.abs(y0).max())
    sides = [(i, sign) for i in range(vmax.size) for sign in (1.0, -1.0)]
    best = math.inf
    for combo in itertools.combinations(sides, k + 1):
        lhs = np.array([[*(sign * null[i]), -1.0] for i, sign in combo])
        if abs(np.linalg.det(lhs)) < 1e-12:
            continue
        x = np.linalg.solve(lhs, [-sign * y0[i] for i, sign in combo])
        if np.abs(y0 + null @ x[:k]).max() <= x[k] + 1e-9:
            best = min(best, float(x[k]))
    return best


def by_linprog(rows, target, vmax):
    """The same LP with the joint velocities as variables, solved by scipy."""
    n = vmax.size
    bound = np.block([[np.eye(n), -vmax[:, None]], [-np.eye(n), -vmax[:, None]]])
    result = linprog(
        np.r_[np.zeros(n), 1.0],
        A_ub=bound,
        b_ub=np.zeros(2 * n),
        A_eq=np.c_[rows, np.zeros(rows.shape[0])],
        b_eq=target,
        bounds=[(None, None)] * n + [(0.0, None)],
    )
    assert result.status == 0, result.message
    return float(result.fun)


def ball_point_jacobian(robot, q, step=1e-6):
    """d(ball point)/dq by central differences of the ball point's position."""

    def point(config):
        pose = robot.tool_pose(config)
        return pose[:3, 3] + BALL_OFFSET * pose[:3, 2]

    columns = []
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = step
        columns.append((point(q + dq) - point(q - dq)) / (2 * step))
    return np.array(columns).T


def random_unit(rng):
    """A random unit vector, shape (3,)."""
    vector = rng.normal(size=3)
    return vector / np.linalg.norm(vector)


def pool_shots(count, speed, seed=7):
    """``count`` seeded Sawyer pool shots at ``speed``: balls and headings over a region."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        ball = (rng.uniform(0.65, 0.85), rng.uniform(-0.05, 0.3), rng.uniform(-0.1, 0.0))
        yield problems.sawyer_pool_shot(speed, ball, heading_deg=rng.uniform(-20.0, 20.0))


def window_ratio(problem, q):
    """Largest ratio over contact, entry and exit, the ends solved by IK from q (None if not)."""
    robot, direction = problem.robot, problem.direction
    ratios = [twist_ratio(robot, q, direction, problem.speed)[0]]
    for point in (problem.entry_point, problem.exit_point):
        try:
            end = solve_ik(robot, point, axis=direction, q_near=q, restarts=0).q
        except UnreachableError:
            return None
        ratios.append(twist_ratio(robot, end, direction, problem.speed)[0])
    return max(ratios)


def turn_ratio(problem, q):
    """The documented room-to-turn estimate at the strike's speed, from IK'd window ends."""
    robot, direction, limits = problem.robot, problem.direction, problem.limits
    entry, leave = (
        solve_ik(robot, point, axis=direction, q_near=q, restarts=0).q
        for point in (problem.entry_point, problem.exit_point)
    )
    worst = 0.0
    for end, rate in (
        (entry, (q - entry) / problem.run_up),  # must have turned before: room behind
        (leave, (leave - q) / problem.follow_through),  # must stop after: room ahead
    ):
        behind = end is entry
        for j in np.flatnonzero(rate):
            up = (rate[j] > 0) != behind
            room = limits.upper[j] - end[j] if up else end[j] - limits.lower[j]
            need = problem.speed * abs(rate[j]) / np.sqrt(2 * limits.acceleration[j] * max(room, 0))
            worst = max(worst, need)
    return worst
