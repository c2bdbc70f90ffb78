r"""How close a pool strike's window can come to the joint limits, by a small NLP on the window.

The contact choice (:mod:`planners.strike.contact`) bounds joint velocities at three configurations
of the strike line. Close to the fastest strike it allows, the line can still be out of
reach: the joints must keep those velocities over the whole window, where the velocities the
line needs change faster than the acceleration and jerk limits let them. :class:`WindowCheck`
answers how near the limits the window can be run, counting the approach into it and the
stop after it: the window (``problem.window``
long, cut into ``intervals`` equal intervals of constant jerk, the optimal-control
transcription's exact triple-integrator steps) with the cue tip on its schedule and the cue
axis on the line at every node, the tip velocity ``speed * direction`` at entry and exit, and
free joint states at both ends, solved for

.. math::

    \min_{x, u, s} s \quad \text{s.t.} \quad |\dot q_{k,i}| \le s\, \dot q_{\max,i},\;
    |\dot q_{k,i} + \tfrac{h}{2} \ddot q_{k,i}| \le s\, \dot q_{\max,i},\;
    |\ddot q_{k,i}| \le s\, \ddot q_{\max,i},\; |u_{k,i}| \le s\, \dddot q_{\max,i},\;
    \Big|\dot q_{0,i} - \frac{\ddot q_{0,i} |\ddot q_{0,i}|}{2 \dddot q_{\max,i}}\Big|
    \le s\, \dot q_{\max,i},\;
    \Big|\dot q_{K,i} + \frac{\ddot q_{K,i} |\ddot q_{K,i}|}{2 \dddot q_{\max,i}}\Big|
    \le s\, \dot q_{\max,i}

with the positions inside their limits. When its optimum keeps within those limits but its
torques (the robot's inverse dynamics at the nodes, gravity included) do not, the same NLP
with the torques bounded by :math:`s` times the effort limits is solved too, and its
optimum is the answer (torque rows make a solve about three times as long, so they come in
only where they can change it). The last two rows
are the approach and the stop: a joint's acceleration changes no faster than its jerk limit,
so a joint that enters the window slowing down was faster by at least
:math:`\ddot q^2 / (2 \dddot q_{\max})` before it, and one that leaves it speeding up gets
that much faster after it. Without them the window of
strike benchmark ball 0 at 1.5 m/s needed 0.997 of the limits, yet its whole NLP stayed
infeasible (even with both ends free) up to limits 1.01 times as large and planned at 1.02;
with them the window needs 1.019. The optimum :math:`s^*` is the least fraction of the
limits the window needs: above 1 the window, and so the strike, is out of reach, whatever
the approach and the stop. It is a local optimum from the contact choice's strike line
(the NLP is not convex), so :math:`s^*` can come out above the global least value: the
planner only uses it to skip further contact configurations once a solve has failed and to
explain its error, never to refuse a strike it has not tried to solve.

A joint motion run :math:`\lambda` times faster along the same path needs :math:`\lambda`,
:math:`\lambda^2` and :math:`\lambda^3` times the velocities, accelerations and jerks, and
at most :math:`\lambda` times the run-out velocities when :math:`\lambda \le 1` (their
acceleration term scales with :math:`\lambda^4`), and torques
:math:`\tau_g + \lambda^2 (\tau - \tau_g)` (:math:`\tau_g` the gravity torques of the same
configuration: inertial and Coriolis terms scale with :math:`\lambda^2`). So the optimum's
peak ratios :math:`(r_v, r_a, r_j)` and its torques give a slower strike speed whose motion
keeps within the limits, :math:`v \min(r_v^{-1}, r_a^{-1/2}, r_j^{-1/3}, \lambda_\tau)` with
:math:`\lambda_\tau^2 = \min (\tau_{\max} - |\tau_g|) / |\tau - \tau_g|` over the nodes and
joints (:attr:`WindowRatio.max_speed`; 0 when gravity alone needs more than an effort limit,
which no slower strike helps), and the quantity with the least factor is the one that binds.
Above the strike speed (a window within the limits) the same formula is an estimate: faster,
the run-outs grow by more. At the strike's own speed, limits :attr:`WindowRatio.ratio` times
as large are the least scale the window can keep within.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.base import CompiledCache
from optraj.planners.ocp.transcription import Rows, jerk_step, strike_node_rows, structure_limits
from optraj.planners.strike.time_optimal_strike import strike_line
from optraj.problems import PoolStrike
from optraj.problems.common import normal_pair
from optraj.robots import JointLimits, Robot, SymbolicModel
from optraj.validation import as_count, as_vector

__all__ = ["WINDOW_INTERVALS", "WindowCheck", "WindowRatio", "run_out"]

FloatArray = NDArray[np.float64]

#: Intervals of the window NLP. On six of the strike benchmark's speed-table balls at 1.35 and
#: 1.5 m/s its optimum moved by at most 0.8 % from 8 to 24 intervals, and a solve at 8 took
#: about half the time of one at 16 (30 to 40 ms).
WINDOW_INTERVALS = 8
#: Most intervals of the window NLP: each adds a node's kinematics and dynamics to it, and
#: past some hundreds its build takes minutes for no better answer.
MAX_WINDOW_INTERVALS = 200
#: Most IPOPT iterations of one window NLP; the solves that converge take 16 to 30.
WINDOW_ITERATIONS = 300
#: IPOPT statuses whose point is a local optimum of the window NLP.
CONVERGED_STATUSES = frozenset({"Solve_Succeeded", "Solved_To_Acceptable_Level"})
QUANTITIES = ("velocity", "acceleration", "jerk", "effort")


@dataclass(frozen=True)
class WindowRatio:
    """The least fraction of the joint limits a strike window was found to need.

    Attributes:
        ratio: Largest of ``velocity``, ``acceleration`` and ``jerk``, and of ``effort`` when
            the torques counted (module docstring): at the strike's speed, the least factor on
            the limits that lets the window keep within them [-].
        velocity: Largest ``|qd_i| / qd_max_i`` at the optimum over the window, between the
            nodes too, and just before and after it (:func:`run_out`) [-].
        acceleration: Largest ``|qdd_i| / qdd_max_i`` [-].
        jerk: Largest ``|jerk_i| / jerk_max_i`` [-].
        effort: Largest ``|tau_i| / tau_max_i`` at the nodes [-]; when it is not above 1
            or the other ratios are, the torques of a point found without torque rows, for
            information only (not in ``ratio``).
        limit: The quantity that caps the speed first (``"velocity"``, ``"acceleration"``,
            ``"jerk"`` or ``"effort"``).
        joint: The joint with the largest ratio of ``limit``.
        required: That joint's peak of ``limit`` [``unit``].
        allowed: Its limit [``unit``].
        unit: The unit of ``required`` and ``allowed``, e.g. ``"rad/s^2"``.
        max_speed: Strike speed at which the optimum's joint path, run slower, keeps within
            the limits; above the strike speed an estimate (module docstring); 0 when gravity
            alone needs more than an effort limit on that path [m/s].
        status: IPOPT's return status.
        iterations: IPOPT iterations.
    """

    ratio: float
    velocity: float
    acceleration: float
    jerk: float
    effort: float
    limit: str
    joint: str
    required: float
    allowed: float
    unit: str
    max_speed: float
    status: str
    iterations: int

    @property
    def converged(self) -> bool:
        """Whether the point is a local optimum (:data:`CONVERGED_STATUSES`)."""
        return self.status in CONVERGED_STATUSES

    def exceeds(self, keep: float = 1.0) -> bool:
        """Whether a converged optimum needs more than ``keep`` of a limit [-]."""
        return self.converged and self.ratio > keep

    def describe(self) -> str:
        """The binding joint, quantity, the window's ratios and what would plan, in words."""
        slower = (
            f"keeps within them run at {self.max_speed:.4g} m/s"
            if self.max_speed > 0.0
            else "no slower strike keeps within them (gravity alone needs more torque)"
        )
        return (
            f"the window check's best strike window needs {self.joint} at {self.required:.4g} "
            f"{self.unit}, {100.0 * self.required / self.allowed:.1f} % of its {self.limit} "
            f"limit {self.allowed:.4g} {self.unit} (peaks: velocity "
            f"{100.0 * self.velocity:.1f} %, acceleration {100.0 * self.acceleration:.1f} %, "
            f"jerk {100.0 * self.jerk:.1f} %, effort {100.0 * self.effort:.1f} % of the "
            f"limits), {slower}, or at this speed with limits {self.ratio:.4g} times as large"
        )


@dataclass(frozen=True)
class _Compiled:
    solver: ca.Function
    lbx: FloatArray
    ubx: FloatArray
    lbg: FloatArray
    ubg: FloatArray
    mid: FloatArray
    half: FloatArray
    scale: tuple[FloatArray, FloatArray, FloatArray]  # velocity, acceleration, jerk limits


class WindowCheck(CompiledCache):
    """The window NLP of a pool strike (module docstring); picklable, one solver per robot.

    Args:
        intervals: Intervals of constant jerk over the window, in [2,
            :data:`MAX_WINDOW_INTERVALS`].
        max_iterations: Most IPOPT iterations of one solve, >= 1.
    """

    def __init__(
        self, intervals: int = WINDOW_INTERVALS, max_iterations: int = WINDOW_ITERATIONS
    ) -> None:
        self.intervals = as_count(intervals, "intervals", 2, MAX_WINDOW_INTERVALS)
        self.max_iterations = as_count(max_iterations, "max_iterations", 1)
        self._compiled: dict[tuple[Any, ...], _Compiled] = {}
        self._lock = threading.Lock()

    def __repr__(self) -> str:
        """Intervals and iteration cap."""
        return f"WindowCheck(intervals={self.intervals}, max_iterations={self.max_iterations})"

    def __call__(self, problem: PoolStrike, q_contact: ArrayLike) -> WindowRatio:
        """Solve the window NLP of ``problem`` from the strike line through ``q_contact``.

        Args:
            problem: The pool strike.
            q_contact: Its contact configuration (e.g. a
                :class:`planners.strike.contact.ContactChoice`'s ``q``) [rad], shape (n,).

        Returns:
            The point's ratios; :attr:`WindowRatio.converged` says whether it is an optimum.

        Raises:
            InvalidInputError: Not a pool strike, or ``q_contact`` of the wrong shape.
            UnreachableError: The strike line through the contact has no IK solution to start
                from.
            SolverError: The solver returned a point that is not finite.
        """
        if not isinstance(problem, PoolStrike):
            raise InvalidInputError(
                f"the window check takes a PoolStrike, got {type(problem).__name__}",
                name="problem",
            )
        limits = problem.limits
        n, k = limits.n, self.intervals
        q = as_vector(q_contact, "q_contact", n)
        compiled = self._compile(problem.robot, limits, effort=False)
        h = float(problem.window) / k
        line = strike_line(problem, k, q_contact=q)
        samples = line.sample(np.minimum(np.linspace(0.0, problem.window, k + 1), line.duration))
        vel, acc, jerk = compiled.scale
        nodes = np.hstack(
            [(samples.q - compiled.mid) / compiled.half, samples.qd / vel, samples.qdd / acc]
        )
        jerks = np.diff(samples.qdd, axis=0) / h / jerk
        start = float(max(np.abs(nodes[:, n:]).max(), np.abs(jerks).max(), 1e-3))
        x0 = np.concatenate([nodes.reshape(-1), jerks.reshape(-1), [start]])
        direction = np.asarray(problem.direction, dtype=float)
        e1, e2 = normal_pair(direction)
        p = np.concatenate([problem.entry_point, direction, e1, e2, [float(problem.speed), h]])
        kinematic = self._solve(problem, compiled, x0, p, effort=False)
        if kinematic.ratio > 1.0 or kinematic.effort <= 1.0 or not kinematic.converged:
            return kinematic
        # Its point keeps the velocities, accelerations and jerks within the limits but not
        # the torques: the NLP with torque rows decides.
        compiled = self._compile(problem.robot, limits, effort=True)
        return self._solve(problem, compiled, x0, p, effort=True)

    def _solve(
        self,
        problem: PoolStrike,
        compiled: _Compiled,
        x0: FloatArray,
        p: FloatArray,
        *,
        effort: bool,
    ) -> WindowRatio:
        """One window NLP solved from ``x0``, and the ratios of its point.

        With ``effort`` (torque rows in the NLP) the effort ratio counts in ``ratio`` and in
        the binding quantity; without, it is the torques of the point, for information.
        """
        limits = problem.limits
        n, k = limits.n, self.intervals
        h = float(problem.window) / k
        vel, acc, jerk = compiled.scale
        result = compiled.solver(
            x0=x0, p=p, lbx=compiled.lbx, ubx=compiled.ubx, lbg=compiled.lbg, ubg=compiled.ubg
        )
        stats = compiled.solver.stats()
        w = np.asarray(result["x"], dtype=float).reshape(-1)
        status = str(stats["return_status"])
        if not np.all(np.isfinite(w)):
            raise SolverError(
                "ipopt",
                status,
                iterations=int(stats["iter_count"]),
                detail="the window NLP's point is not finite",
            )
        states = w[: (k + 1) * 3 * n].reshape(k + 1, 3 * n)
        jerks = w[(k + 1) * 3 * n : -1].reshape(k, n)
        q_nodes = compiled.mid + compiled.half * states[:, :n]
        tau = problem.robot.inverse_dynamics(
            q_nodes, vel * states[:, n : 2 * n], acc * states[:, 2 * n :]
        )
        peaks = (
            _velocity_peaks(states, jerks, h, compiled.scale),
            np.abs(states[:, 2 * n :]).max(axis=0),  # linear on an interval: nodes suffice
            np.abs(jerks).max(axis=0),
            (np.abs(tau) / limits.effort).max(axis=0),
        )
        tops = [float(peak.max()) for peak in peaks]
        # The speed factor each quantity allows: velocity ~ v, acceleration ~ v^2, jerk ~ v^3,
        # the torques' inertial and Coriolis part ~ v^2 on top of gravity.
        factors = [
            math.inf if top <= 0.0 else top ** (-1.0 / power)
            for power, top in enumerate(tops[:3], start=1)
        ]
        if effort:  # the effort factor splits the torque into gravity and a v^2 part
            gravity = problem.robot.gravity_torque(q_nodes)
            factors.append(_effort_factor(tau, gravity, limits.effort))
        else:
            factors.append(math.inf)
        which = int(np.argmin(factors))
        joint = int(np.argmax(peaks[which]))
        allowed = float((vel, acc, jerk, limits.effort)[which][joint])
        return WindowRatio(
            ratio=max(tops) if effort else max(tops[:3]),
            velocity=tops[0],
            acceleration=tops[1],
            jerk=tops[2],
            effort=tops[3],
            limit=QUANTITIES[which],
            joint=limits.names[joint],
            required=float(peaks[which][joint]) * allowed,
            allowed=allowed,
            unit=limits.unit(QUANTITIES[which], joint),
            max_speed=float(problem.speed) * min(factors),
            status=status,
            iterations=int(stats["iter_count"]),
        )

    def _compile(self, robot: Robot, limits: JointLimits, *, effort: bool) -> _Compiled:
        key = (robot.fingerprint, structure_limits(limits), self.intervals, effort)
        with self._lock:
            compiled = self._compiled.get(key)
        if compiled is None:
            compiled = _compile(robot, limits, self.intervals, self.max_iterations, effort)
            with self._lock:
                compiled = self._compiled.setdefault(key, compiled)
        return compiled


def _effort_factor(tau: FloatArray, gravity: FloatArray, effort: FloatArray) -> float:
    """The largest speed factor ``lam`` <= inf with ``|g| + lam^2 |tau - g| <= effort`` [-].

    Args:
        tau: Torques at the nodes [N m or N], shape (k + 1, n).
        gravity: The gravity torques of the same configurations, shape (k + 1, n).
        effort: Effort limits, shape (n,).

    Returns:
        0 when gravity alone passes a limit somewhere; inf when nothing moves.
    """
    room = effort - np.abs(gravity)
    if np.any(room < 0.0):
        return 0.0
    moving = np.abs(tau - gravity)
    with np.errstate(divide="ignore"):
        squares = np.where(moving > 0.0, room / moving, math.inf)
    return float(math.sqrt(squares.min()))


def run_out(
    velocity: FloatArray | ca.SX,
    acceleration: FloatArray | ca.SX,
    jerk: FloatArray | ca.SX,
    sign: float,
) -> FloatArray | ca.SX:
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


def _velocity_peaks(
    states: FloatArray,
    jerks: FloatArray,
    h: float,
    scale: tuple[FloatArray, FloatArray, FloatArray],
) -> FloatArray:
    """Each joint's largest ``|qd| / qd_max`` over the window, between the nodes too [-].

    Args:
        states: Scaled node states ``(zq, zv, za)``, shape (k + 1, 3 n).
        jerks: Scaled jerks, shape (k, n).
        h: Interval length [s].
        scale: Velocity, acceleration and jerk limits, each shape (n,).

    Returns:
        Shape (n,): the velocity is quadratic on an interval, so its peak is at a node or
        where the acceleration crosses zero inside the interval; the velocities just before
        the first node and after the last (:func:`run_out`) count too.
    """
    vel, acc, jerk = scale
    n = vel.size
    v0, a0, u = vel * states[:-1, n : 2 * n], acc * states[:-1, 2 * n :], jerk * jerks
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = np.where(u != 0.0, -a0 / u, -1.0)  # [s] after the interval's start
    inside = (turn > 0.0) & (turn < h)
    at_turn = np.where(inside, np.abs(v0 + a0 * turn + 0.5 * u * turn**2), 0.0)
    ends = np.abs(
        [
            run_out(vel * states[0, n : 2 * n], acc * states[0, 2 * n :], jerk, -1.0),
            run_out(vel * states[-1, n : 2 * n], acc * states[-1, 2 * n :], jerk, 1.0),
        ]
    )
    nodes = np.abs(states[:, n : 2 * n]).max(axis=0)
    return np.maximum.reduce([nodes, (at_turn / vel).max(axis=0), ends.max(axis=0) / vel])


def _compile(
    robot: Robot, limits: JointLimits, k: int, max_iterations: int, effort_rows: bool
) -> _Compiled:
    """The window NLP: node states and jerks scaled by the limits, then the slack ``s``.

    With ``effort_rows`` the torques at the nodes are bounded by ``s`` times the effort
    limits too (the robot's RNEA: about 3 times the solve time, 4 times the build time).
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
        return mid + half * z[:n], vel * z[n : 2 * n], acc * z[2 * n :], z

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
            # iterates ran off on an easy 1 m/s strike (ratio 1000 after 300 iterations).
            # From 1e-3 all 36 windows of a sample of 1, 1.35 and 1.5 m/s strikes converged,
            # in 16 to 30 iterations.
            "ipopt.mu_init": 1e-3,
            "ipopt.mumps_permuting_scaling": 0,
            "ipopt.mumps_scaling": 0,
        },
    )
    node_lower = np.concatenate([-np.ones(n), np.full(2 * n, -np.inf)])
    lbx = np.concatenate([np.tile(node_lower, k + 1), np.full(k * n, -np.inf), [0.0]])
    ubx = np.concatenate([np.tile(-node_lower, k + 1), np.full(k * n, np.inf), [np.inf]])
    return _Compiled(
        solver=solver,
        lbx=lbx,
        ubx=ubx,
        lbg=np.concatenate(rows.lower),
        ubg=np.concatenate(rows.upper),
        mid=mid,
        half=half,
        scale=(vel, acc, jerk),
    )
