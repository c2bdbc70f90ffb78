r"""The window NLP of a pool strike: its variables, its rows and its first point.

The window (``problem.window`` long, cut into k equal intervals of constant jerk, the
optimal-control transcription's exact triple-integrator steps) with the cue tip on its schedule
and the cue axis on the line at every node, the tip velocity ``speed * direction`` at entry and
exit, and free joint states at both ends, solved for

.. math::

    \min_{x, u, s} s \quad \text{s.t.} \quad |\dot q_{k,i}| \le s\, \dot q_{\max,i},\;
    |\dot q_{k,i} + \tfrac{h}{2} \ddot q_{k,i}| \le s\, \dot q_{\max,i},\;
    |\ddot q_{k,i}| \le s\, \ddot q_{\max,i},\; |u_{k,i}| \le s\, \dddot q_{\max,i},\;
    \Big|\dot q_{0,i} - \frac{\ddot q_{0,i} |\ddot q_{0,i}|}{2 \dddot q_{\max,i}}\Big|
    \le s\, \dot q_{\max,i},\;
    \Big|\dot q_{K,i} + \frac{\ddot q_{K,i} |\ddot q_{K,i}|}{2 \dddot q_{\max,i}}\Big|
    \le s\, \dot q_{\max,i}

with the positions inside their limits, and optionally the torques (the robot's inverse
dynamics at the nodes, gravity included) bounded by :math:`s` times the effort limits. The
last two rows are the approach and the stop (:func:`run_out`): a joint's acceleration changes
no faster than its jerk limit, so a joint that enters the window slowing down was faster by at
least :math:`\ddot q^2 / (2 \dddot q_{\max})` before it, and one that leaves it speeding up
gets that much faster after it; without them a window can look within the limits although no
motion through it is.

:func:`build_window_nlp` builds the NLP once per robot, limits and interval count as a
:class:`WindowNLP`; :func:`first_point` and :func:`parameters` give a solve its start (the
contact choice's strike line) and its strike, and :func:`split_point` reads its result.
:class:`planners.strike.window_check.WindowCheck` caches, solves and judges it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast, overload

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.task_rows import strike_node_rows
from optraj.planners.ocp.transcription import Rows, jerk_step
from optraj.planners.strike.time_optimal_strike import strike_line
from optraj.problems import PoolStrike
from optraj.problems.common import normal_pair
from optraj.robots import JointLimits, Robot, SymbolicModel

__all__ = ["WindowNLP", "build_window_nlp", "first_point", "parameters", "run_out", "split_point"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class WindowNLP:
    """The compiled window NLP and its bounds.

    The variables are the k + 1 node states scaled by the limits (``(q - mid) / half``,
    ``qd / qd_max``, ``qdd / qdd_max``, each shape (n,)), then the k interval jerks over the
    jerk limits, then the slack ``s``; the parameters are the line's entry point, its
    direction and the two unit vectors across it, the strike speed and the interval length
    (:func:`parameters`).

    Attributes:
        solver: IPOPT through CasADi, ``solver(x0=, p=, lbx=, ubx=, lbg=, ubg=)``.
        lbx: Lower bounds of the variables, shape ((k + 1) 3 n + k n + 1,).
        ubx: Upper bounds of the variables, the same shape.
        lbg: Lower bounds of the rows.
        ubg: Upper bounds of the rows.
        mid: Middle of each joint's position range [rad or m], shape (n,).
        half: Half of each joint's position range [rad or m], shape (n,).
        scale: The velocity, acceleration and jerk limits, each shape (n,).
    """

    solver: ca.Function
    lbx: FloatArray
    ubx: FloatArray
    lbg: FloatArray
    ubg: FloatArray
    mid: FloatArray
    half: FloatArray
    scale: tuple[FloatArray, FloatArray, FloatArray]


@overload
def run_out(velocity: ca.SX, acceleration: ca.SX, jerk: FloatArray, sign: float) -> ca.SX: ...


@overload
def run_out(
    velocity: FloatArray, acceleration: FloatArray, jerk: FloatArray, sign: float
) -> FloatArray: ...


@overload
def run_out(velocity: float, acceleration: float, jerk: float, sign: float) -> float: ...


def run_out(velocity: Any, acceleration: Any, jerk: Any, sign: float) -> Any:
    """The velocity a joint reaches when its acceleration, changed at the jerk limit, is zero.

    Forward in time (``sign`` +1) from a state, backward (``sign`` -1) into it. No jerk
    profile within the limit takes the acceleration to zero with less change of velocity, and
    the velocity changes monotonically on the way: so the joint's speed over that stretch,
    the state included, peaks at least at the magnitude of this value. Element-wise on NumPy
    arrays and CasADi expressions alike.

    Args:
        velocity: Joint velocity [rad/s or m/s].
        acceleration: Joint acceleration [rad/s^2 or m/s^2].
        jerk: Jerk limit, > 0 [rad/s^3 or m/s^3].
        sign: +1 after the state, -1 before it.

    Returns:
        ``velocity + sign * acceleration * |acceleration| / (2 * jerk)``, in the velocity's unit.
    """
    return velocity + sign * acceleration * abs(acceleration) / (2.0 * jerk)


def first_point(nlp: WindowNLP, problem: PoolStrike, q_contact: FloatArray, k: int) -> FloatArray:
    """The NLP's variables along the strike line through ``q_contact``, to start a solve from.

    Args:
        nlp: The window NLP of ``problem``'s robot and limits.
        problem: The pool strike.
        q_contact: Its contact configuration [rad], shape (n,).
        k: The NLP's intervals.

    Raises:
        UnreachableError: The strike line through the contact has no IK solution.
    """
    n = q_contact.size
    h = float(problem.window) / k
    line = strike_line(problem, k, q_contact=q_contact)
    samples = line.sample(np.minimum(np.linspace(0.0, problem.window, k + 1), line.duration))
    vel, acc, jerk = nlp.scale
    nodes = np.hstack([(samples.q - nlp.mid) / nlp.half, samples.qd / vel, samples.qdd / acc])
    jerks = np.diff(samples.qdd, axis=0) / h / jerk
    start = float(max(np.abs(nodes[:, n:]).max(), np.abs(jerks).max(), 1e-3))
    return np.concatenate([nodes.reshape(-1), jerks.reshape(-1), [start]])


def parameters(problem: PoolStrike, k: int) -> FloatArray:
    """The NLP's parameters for ``problem``: entry point, direction, e1, e2, speed, h."""
    h = float(problem.window) / k
    direction = np.asarray(problem.direction, dtype=float)
    e1, e2 = normal_pair(direction)
    return np.concatenate([problem.entry_point, direction, e1, e2, [float(problem.speed), h]])


def split_point(w: FloatArray, k: int, n: int) -> tuple[FloatArray, FloatArray]:
    """The scaled node states, shape (k + 1, 3 n), and jerks, shape (k, n), of a point."""
    states = w[: (k + 1) * 3 * n].reshape(k + 1, 3 * n)
    jerks = w[(k + 1) * 3 * n : -1].reshape(k, n)
    return states, jerks


def build_window_nlp(
    robot: Robot, limits: JointLimits, k: int, max_iterations: int, effort_rows: bool
) -> WindowNLP:
    """Build the window NLP (module docstring): variables and parameters as :class:`WindowNLP`.

    Args:
        robot: The robot.
        limits: Its joint limits.
        k: Intervals over the window, >= 2.
        max_iterations: Most IPOPT iterations of one solve.
        effort_rows: Bound the torques at the nodes by ``s`` times the effort limits too (the
            robot's RNEA, which makes the NLP much longer to build and to solve).
    """
    symbolic = SymbolicModel(robot)
    lower, upper = np.asarray(limits.lower), np.asarray(limits.upper)
    vel, acc, jerk, effort = (
        np.asarray(limits.velocity),
        np.asarray(limits.acceleration),
        np.asarray(limits.jerk),
        np.asarray(limits.effort),
    )
    n = lower.size
    mid, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
    w = ca.SX.sym("w", (k + 1) * 3 * n + k * n + 1)
    p = ca.SX.sym("p", 14)
    entry, d, e1, e2, speed, h = p[0:3], p[3:6], p[6:9], p[9:12], p[12], p[13]
    s = w[-1]
    tool = (
        symbolic.frame_position(robot.tool_frame),
        symbolic.frame_rotation(robot.tool_frame),
        symbolic.frame_jacobian(robot.tool_frame),
    )
    line = {"direction": d, "e1": e1, "e2": e2, "speed": speed}
    rows = Rows()

    def within(scaled: ca.SX) -> None:
        """``|scaled| <= s``, element-wise."""
        rows.add("limits", scaled - s, -np.inf, 0.0)
        rows.add("limits", scaled + s, 0.0, np.inf)

    def state(node: int) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
        z = w[node * 3 * n : (node + 1) * 3 * n]
        # An array times an SX is an SX (CasADi takes the operation over from NumPy).
        q = cast(ca.SX, mid + half * z[:n])
        return q, cast(ca.SX, vel * z[n : 2 * n]), cast(ca.SX, acc * z[2 * n :]), z

    cost = s
    rnea = symbolic.rnea() if effort_rows else None  # only the effort rows need it
    for node in range(k + 1):
        q, qd, qdd, z = state(node)
        strike_node_rows(rows, tool, line, q, qd, entry + speed * h * node * d, node in (0, k))
        if node in (0, k):
            # The approach into the window and the stop after it (module docstring).
            within(run_out(qd, qdd, jerk, -1.0 if node == 0 else 1.0) / vel)
        within(z[n:])
        if rnea is not None:
            within(rnea(q, qd, qdd) / effort)
        if node == k:
            break
        zu = w[(k + 1) * 3 * n + node * n : (k + 1) * 3 * n + (node + 1) * n]
        q1, v1, a1, _ = state(node + 1)
        q_next, v_next, a_next = jerk_step(h, q, qd, qdd, jerk * zu)
        step = ca.vertcat((q1 - q_next) / half, (v1 - v_next) / vel, (a1 - a_next) / acc)
        rows.add("dynamics", step, 0.0, 0.0)
        within(ca.vertcat((qd + h / 2 * qdd) / vel, zu))  # velocity's middle Bernstein term
        cost += 1e-6 * ca.sumsqr(zu)  # a unique jerk where the slack leaves it free
    solver = ca.nlpsol(
        "window_check",
        "ipopt",
        {"x": w, "p": p, "f": cost, "g": ca.vertcat(*rows.rows)},
        {
            "expand": True,
            "print_time": False,
            "ipopt.print_level": 0,
            "ipopt.sb": "yes",
            "ipopt.tol": 1e-6,
            "ipopt.max_iter": max_iterations,
            # The slack meets hundreds of limit rows, each with a barrier term: from IPOPT's
            # default barrier parameter (0.1) their pull outweighs the objective and the
            # iterates can run off even on an easy strike; a smaller start keeps them near it.
            "ipopt.mu_init": 1e-3,
            "ipopt.mumps_permuting_scaling": 0,
            "ipopt.mumps_scaling": 0,
        },
    )
    node_lower = np.concatenate([-np.ones(n), np.full(2 * n, -np.inf)])
    lbx = np.concatenate([np.tile(node_lower, k + 1), np.full(k * n, -np.inf), [0.0]])
    ubx = np.concatenate([np.tile(-node_lower, k + 1), np.full(k * n, np.inf), [np.inf]])
    return WindowNLP(
        solver=solver,
        lbx=lbx,
        ubx=ubx,
        lbg=np.concatenate(rows.lower),
        ubg=np.concatenate(rows.upper),
        mid=mid,
        half=half,
        scale=(vel, acc, jerk),
    )
