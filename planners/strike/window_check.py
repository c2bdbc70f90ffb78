r"""How close a pool strike's window can come to the joint limits, by a small NLP on the window.

The contact choice (:mod:`planners.strike.contact`) bounds joint velocities at three
configurations of the strike line. Close to the fastest strike it allows, the line can still be
out of reach: the joints must keep those velocities over the whole window, where the velocities
the line needs change faster than the acceleration and jerk limits let them.
:class:`WindowCheck` answers how near the limits the window can be run, counting the approach
into it and the stop after it: it solves the window NLP of
:mod:`planners.strike.window_nlp`, the least slack :math:`s` by which the limits can be scaled
with the window within them. When its optimum keeps within the velocity, acceleration and jerk
limits but its torques (the robot's inverse dynamics at the nodes, gravity included) do not,
the same NLP with torque rows is solved too, and its optimum is the answer (torque rows make a
solve much longer, so they come in only where they can change it). The optimum :math:`s^*` is
the least fraction of the limits the window needs: above 1 the window, and so the strike, is
out of reach, whatever the approach and the stop. It is a local optimum from the contact
choice's strike line (the NLP is not convex), so :math:`s^*` can come out above the global
least value: the planner only uses it to skip further contact configurations once a solve has
failed and to explain its error, never to refuse a strike it has not tried to solve.

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
as large are the least scale the window can keep within. Usage::

    check = WindowCheck()  # keeps one compiled NLP per robot and limits
    window = check(problem, choose_contact(problem).q)
    if window.exceeds():
        print(window.describe())
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.base import CompiledCache
from optraj.planners.ocp.transcription import structure_limits
from optraj.planners.strike.window_nlp import (
    WindowNLP,
    build_window_nlp,
    first_point,
    parameters,
    run_out,
    split_point,
)
from optraj.problems import PoolStrike
from optraj.robots import JointLimits, Robot
from optraj.validation import as_count, as_vector

__all__ = ["WINDOW_INTERVALS", "WindowCheck", "WindowRatio", "run_out"]

FloatArray = NDArray[np.float64]

#: Intervals of the window NLP: more move its optimum little and make each solve longer.
WINDOW_INTERVALS = 8
#: Most intervals of the window NLP: each adds a node's kinematics and dynamics to it, and
#: past some hundreds its build takes minutes for no better answer.
MAX_WINDOW_INTERVALS = 200
#: Most IPOPT iterations of one window NLP, well above what a converging solve takes.
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
        self._compiled: dict[tuple[Any, ...], WindowNLP] = {}
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
        q = as_vector(q_contact, "q_contact", limits.n)
        compiled = self._compile(problem.robot, limits, effort=False)
        x0 = first_point(compiled, problem, q, self.intervals)
        p = parameters(problem, self.intervals)
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
        compiled: WindowNLP,
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
        states, jerks = split_point(w, k, n)
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

    def _compile(self, robot: Robot, limits: JointLimits, *, effort: bool) -> WindowNLP:
        key = (robot.fingerprint, structure_limits(limits), self.intervals, effort)
        with self._lock:
            compiled = self._compiled.get(key)
        if compiled is None:
            compiled = build_window_nlp(robot, limits, self.intervals, self.max_iterations, effort)
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
