r"""Differential IK as a QP on OSQP: the pseudo-inverse's replacement that keeps every limit.

Each step solves, for the joint velocity command :math:`\dot q`,

.. math::

    \min_{\dot q} \; \tfrac12 \|J \dot q - v_{cmd}\|_W^2 + \tfrac{\lambda}{2} \|\dot q\|^2
        + \tfrac{w}{2} \|\dot q - (\dot q_{ref} + k (q_{ref} - q))\|^2

    \text{s.t.} \quad |\dot q| \le \dot q_{max}, \quad
    |\dot q - \dot q_{last}| \le \ddot q_{max} \Delta t, \quad
    \text{position limits over the next step, with room to brake}

with :math:`v_{cmd}` from the same Cartesian PID law as
:class:`~controllers.pseudo_inverse_pid.PseudoInversePID`. The posture term moves with the
planned joint velocity :math:`\dot q_{ref}`, so that a redundant arm's self-motion follows the
plan's rather than lagging it (``posture_velocity=False``: a posture at rest). The command
carries the plan's feed-forward torque :attr:`Reference.tau
<controllers.controller.Reference>` (``feedforward=False``: none), which the plant adds to its
velocity servo. The pieces come from
:mod:`controllers.qp_terms` and are added up by :func:`~controllers.qp_terms.combine`. The
sparse OSQP problem is set up once; each step only updates its numbers (``H``'s upper
triangle, ``c`` and the bounds) and starts from the last solution.

From one control step to the next the set of bounds that bind rarely changes. So a step first
solves the QP exactly on the last step's active set, the bounds that bound then held as
equalities and the other joints free: one small linear solve, accepted only when it meets
every optimality condition (free joints within their bounds, the multipliers of the held ones
pushing outwards). This is the QP's exact solution, not an approximation. When the guess fails
the conditions (the active set changed), the set is changed (free joints that left their
bounds are held, held joints pushing inwards are freed) and solved again, a primal-dual
active-set method; only when that does not settle within a few changes does OSQP solve the
step, and its multipliers give the new active set. :attr:`DiffIKQP.diagnostics` says which
path a step took. With extra constraint rows every step goes to OSQP.

Without extra constraint rows, a step by default does not assemble the pieces at all: one
CasADi function (:class:`~controllers.fused_step.FusedStep`) computes the tool pose and
Jacobian, the PID law, the QP's numbers and the exact solution on the last active set in one
call, optionally compiled to C (``evaluation="compiled"``). The pieces remain the reference
(and :meth:`DiffIKQP.build` returns them); the two agree to round-off.

When OSQP does not return a solution within the bounds, the controller sends a safe command
instead: the last command brought towards rest at the acceleration limit. It keeps the
velocity and acceleration limits, and the braking room of the position bounds that held on the
steps before stops the joints short of their position limits; extra constraint rows are not
considered. :attr:`Command.status` says so, and the fallback carries no feed-forward torque.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import osqp
import scipy.sparse as sparse
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from optraj.controllers.cartesian_pid import CartesianPID, tool_kinematics
from optraj.controllers.controller import Command, Controller, Reference, State
from optraj.controllers.fused_step import FusedStep, StepSettings
from optraj.controllers.qp_terms import (
    QP,
    Constraint,
    acceleration_bounds,
    combine,
    damping_objective,
    identity,
    position_bounds,
    posture_objective,
    task_objective,
    task_weights,
    velocity_bounds,
)
from optraj.errors import InvalidInputError, UnsupportedModelError
from optraj.problems.common import check_robot
from optraj.robots import JointLimits, Robot
from optraj.validation import (
    as_array,
    as_choice,
    as_count,
    as_flag,
    as_fraction,
    as_number,
    as_positive,
)

__all__ = ["DiffIKQP"]

FloatArray = NDArray[np.float64]

#: A solution may leave its bounds by this much (relative to the bound's scale) before it is
#: rejected; within it, the solution is projected onto the bounds.
BOUND_TOLERANCE = 1e-6
#: Default changes of the active set tried per step before OSQP decides: from one control
#: period to the next the bounds that hold rarely change by more than one or two.
ACTIVE_SET_CHANGES = 6
#: Most changes one may ask for: each is unrolled into the compiled step, so the step's
#: size (and its compile time) grows with it.
MAX_ACTIVE_SET_CHANGES = 64
#: How a step computes its QP (see DiffIKQP).
EVALUATIONS: tuple[str, ...] = ("fused", "compiled", "pieces")
#: OSQP's infinity.
OSQP_INFINITY = 1e30
#: OSQP outcomes whose ``x`` is used: solved, solved inaccurately, or stopped at the iteration
#: cap; the latter two only when the solution then passes the bound check.
USABLE = frozenset(
    int(status)
    for status in (
        osqp.SolverStatus.OSQP_SOLVED,
        osqp.SolverStatus.OSQP_SOLVED_INACCURATE,
        osqp.SolverStatus.OSQP_MAX_ITER_REACHED,
    )
)


class DiffIKQP(Controller):
    """Cartesian PID through a limit-aware QP instead of the pseudo-inverse.

    Args:
        robot: The robot.
        kp, ki, kd, integral_limit: The Cartesian PID law, as in
            :class:`~controllers.cartesian_pid.CartesianPID`.
        task: ``"pose"`` (6-D), or ``"axis"`` (5-D: the angular velocity about the tool z
            axis is free, for a cue whose roll does not matter).
        weights: Task weights [linear, angular] of the twist error [-].
        damping: Damping ``lambda`` on the joint velocity [-], > 0 keeps the QP strictly
            convex at singularities.
        posture_weight: Weight ``w`` of the pull towards the planned joint positions [-];
            sets the self-motion of a redundant arm. 0 turns it off.
        posture_gain: Rate ``k`` of that pull [1/s].
        posture_velocity: Whether the posture moves with the planned joint velocity
            (``qd_ref + k (q_ref - q)``); False: only the pull ``k (q_ref - q)`` towards a
            posture at rest.
        feedforward: Whether the command carries the plan's feed-forward torque
            (``reference.tau``); False: ``Command.tau`` is None.
        limits: Limits to respect; the robot's when None.
        velocity_scale: Fraction of the velocity limits the command may use, in [1e-6, 1].
        position_gain: Fraction of the distance to a position limit one step may cover.
        constraints: Extra constant rows ``lower <= G qd <= upper`` (e.g. a Cartesian speed
            cap along a direction), added to every step's QP.
        tolerance: OSQP's absolute and relative tolerance.
        max_iterations: OSQP's iteration cap per step.
        active_set_changes: Without extra constraint rows the QP has bounds only: each step
            first solves it exactly on the last step's active set, then changes that set up
            to this many times (a primal-dual active-set method, each change one linear
            solve), and calls OSQP only when that does not settle. 0: only the last set;
            at most :data:`MAX_ACTIVE_SET_CHANGES`.
        evaluation: How a step without extra constraint rows computes its QP: ``"fused"``
            (default), one CasADi function of the state for the kinematics, the PID law, the
            QP's numbers and the exact solve on the last active set
            (:class:`~controllers.fused_step.FusedStep`); ``"compiled"``, the same compiled to
            C with gcc (about 1 s when the controller is made or unpickled, then a few
            microseconds a step); ``"pieces"``, :meth:`build` from
            :mod:`controllers.qp_terms` at every step. All three give the same command to
            round-off; the fused ones hand over to the pieces when the boxes do not overlap or
            the 6-D task's orientation error is near half a turn
            (``diagnostics["evaluation"]`` says which built a step). ``"fused"`` becomes
            ``"pieces"`` for a robot with joints :class:`robots.SymbolicModel` does not
            handle.

    Raises:
        InvalidInputError: A robot that is not a robots.Robot, a bad gain, weight, scale,
            tolerance, switch or constraints, or limits for another joint count.
        UnknownNameError: An unknown task or evaluation.
        CompilerError: ``evaluation="compiled"`` and the C code did not compile.
        UnsupportedModelError: ``evaluation="compiled"`` for a robot with joints
            :class:`robots.SymbolicModel` does not handle.
    """

    def __init__(
        self,
        robot: Robot,
        kp: ArrayLike = 20.0,
        ki: ArrayLike = 5.0,
        kd: ArrayLike = 0.0,
        integral_limit: ArrayLike = (0.01, 0.05),
        task: Literal["pose", "axis"] = "pose",
        weights: tuple[float, float] = (1.0, 1.0),
        damping: float = 1e-6,
        posture_weight: float = 1e-3,
        posture_gain: float = 5.0,
        limits: JointLimits | None = None,
        velocity_scale: float = 1.0,
        position_gain: float = 0.95,
        constraints: Sequence[Constraint] = (),
        tolerance: float = 1e-7,
        max_iterations: int = 1000,
        active_set_changes: int = ACTIVE_SET_CHANGES,
        evaluation: Literal["fused", "compiled", "pieces"] = "fused",
        posture_velocity: bool = True,
        feedforward: bool = True,
    ) -> None:
        self.robot = check_robot(robot)
        self.pid = CartesianPID(kp, ki, kd, integral_limit, task)
        pair = as_array(weights, "weights", (2,))
        if np.any(pair < 0.0) or not np.any(pair > 0.0):
            raise InvalidInputError(
                f"weights [linear, angular] must be >= 0 and not both 0, got {pair.tolist()}",
                name="weights",
            )
        self.weights = (float(pair[0]), float(pair[1]))
        self.damping = as_positive(damping, "damping")
        self.posture_weight = as_number(posture_weight, "posture_weight", minimum=0.0)
        self.posture_gain = as_positive(posture_gain, "posture_gain", "1/s")
        self.posture_velocity = as_flag(posture_velocity, "posture_velocity")
        self.feedforward = as_flag(feedforward, "feedforward")
        if limits is not None and not isinstance(limits, JointLimits):
            raise InvalidInputError(
                f"limits must be a robots.JointLimits, got {type(limits).__name__}", name="limits"
            )
        self.limits = robot.limits if limits is None else limits
        if self.limits.n != robot.dof:
            raise InvalidInputError(
                f"limits cover {self.limits.n} joints, robot {robot.name!r} has {robot.dof}",
                name="limits",
            )
        self.velocity_scale = as_fraction(velocity_scale, "velocity_scale")
        self.position_gain = as_fraction(position_gain, "position_gain")
        if not isinstance(constraints, (list, tuple)):
            raise InvalidInputError(
                f"constraints must be a list or tuple of controllers.Constraint, got "
                f"{type(constraints).__name__}",
                name="constraints",
            )
        self.constraints = tuple(_checked_rows(c, robot.dof) for c in constraints)
        self.tolerance = as_positive(tolerance, "tolerance")
        self.max_iterations = as_count(max_iterations, "max_iterations", minimum=1)
        self.active_set_changes = as_count(
            active_set_changes, "active_set_changes", maximum=MAX_ACTIVE_SET_CHANGES
        )
        self.evaluation = as_choice(evaluation, "evaluation", EVALUATIONS)
        # Pieces that do not change from step to step, built once.
        self._damping = damping_objective(robot.dof, self.damping)
        self._velocity = velocity_bounds(self.limits.velocity, self.velocity_scale)
        self._pose_weights = np.diag(task_weights(*self.weights)).copy()  # W is diagonal
        self._solver: _Workspace | None = None
        self._last = np.zeros(robot.dof)
        self._rest = np.zeros(robot.dof)  # the posture's velocity without posture_velocity
        self._active = _ActiveSet.none(robot.dof)
        self._fused: FusedStep | None = None
        self._fused_active: _ActiveSet | None = None  # the set FusedStep holds
        if self._uses_fused:
            try:
                self._fused = self._make_fused()
            except UnsupportedModelError:
                if evaluation == "compiled":
                    raise
                self.evaluation = "pieces"
        #: What the last step did: ``"evaluation"`` (``"fused"``, ``"compiled"`` or
        #: ``"pieces"``), ``"solver"`` (``"active set"`` or ``"osqp"``), OSQP's status and
        #: iterations, relaxed bounds, fallback.
        self.diagnostics: dict[str, Any] = {}

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["_solver"] = None  # OSQP's workspace is rebuilt on the next step
        state["_fused"] = None  # so is the CasADi function
        state["_fused_active"] = None
        return state

    @property
    def _uses_fused(self) -> bool:
        return self.evaluation != "pieces" and not self.constraints

    def _make_fused(self) -> FusedStep:
        compiled = self.evaluation == "compiled"
        return FusedStep(self.robot, self._step_settings(), compiled=compiled)

    def _step_settings(self) -> StepSettings:
        """This controller's settings, as a :class:`FusedStep` is built from them."""
        return StepSettings(
            self.pid,
            self.weights,
            self.damping,
            self.posture_weight,
            self.posture_gain,
            self.limits,
            self.velocity_scale,
            self.position_gain,
            _ActiveSet.SLACK,
            self.active_set_changes,
        )

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "differential-IK QP"

    def reset(self, state: State) -> None:
        """Clear the integral and the warm start; the measured velocity becomes the last command."""
        self.pid.reset()
        self._solver = None
        self._last = np.array(state.qd, dtype=float)
        self._active = _ActiveSet.none(self.robot.dof)
        self.diagnostics = {}

    # ------------------------------------------------------------------------------ build

    def build(self, state: State, reference: Reference, dt: float) -> QP:
        """The QP of one step, without solving it (to inspect or test the pieces).

        Args:
            state: The measured state now.
            reference: The planned motion now.
            dt: Control period [s].
        """
        limits = self.limits
        T, J = tool_kinematics(self.robot, state.q)
        v = self.pid.twist(T, J, state.qd, reference, dt)
        if self.pid.task == "axis":
            W = task_weights(*self.weights, axis=T[:3, 2])
        else:
            W = self._pose_weights
        objectives = [task_objective(J, v, W), self._damping]
        if self.posture_weight > 0.0:
            objectives.append(
                posture_objective(
                    state.q,
                    reference.q,
                    self.posture_weight,
                    self.posture_gain,
                    reference.qd if self.posture_velocity else None,
                )
            )
        bounds = [
            self._velocity,
            acceleration_bounds(self._last, limits.acceleration, dt),
            position_bounds(
                state.q, limits.lower, limits.upper, limits.acceleration, dt, self.position_gain
            ),
        ]
        return combine(objectives, bounds, self.constraints)

    # ------------------------------------------------------------------------------ solve

    def step(self, state: State, reference: Reference, dt: float) -> Command:
        """Build and solve this step's QP; a safe fallback when it cannot be solved.

        The command carries ``reference.tau`` as its feed-forward torque when
        ``feedforward``, except a fallback, which carries none.
        """
        command = self._fused_step(state, reference, dt) if self._uses_fused else None
        evaluation = self.evaluation
        if command is None:
            command = self.solve(self.build(state, reference, dt), dt)
            evaluation = "pieces"
        self.diagnostics["evaluation"] = evaluation
        self._last = command.qd
        if self.feedforward and not command.fallback and reference.tau is not None:
            command = command._replace(tau=reference.tau)
        return command

    def _fused_step(self, state: State, reference: Reference, dt: float) -> Command | None:
        """The step through :class:`FusedStep`; None when the pieces must build it."""
        fused = self._fused
        if fused is None:  # after unpickling
            fused = self._fused = self._make_fused()
        if self._fused_active is not self._active:
            fused.set_active(self._active.upper, self._active.lower)
            self._fused_active = self._active
        ok, fallback = fused(
            state.q,
            state.qd,
            reference.T_world_tool,
            reference.twist,
            reference.q,
            reference.qd if self.posture_velocity else self._rest,
            self.pid._integral,  # the PID's own state, advanced here by the same law
            self._last,
            dt,
        )
        if fallback:
            return None
        self.pid._integral = fused.integral.copy()
        x = fused.x
        if not ok and fused.search():  # the active set changed, and settled within the tries
            x = fused.searched_x
            self._active = _ActiveSet(fused.searched_upper > 0.5, fused.searched_lower > 0.5)
            ok = True
        if ok:
            self.diagnostics = {"solver": "active set", "relaxed": ()}
            return Command(np.minimum(np.maximum(x, fused.lower), fused.upper))
        n = self.robot.dof
        qp = QP(
            fused.H.copy(),
            fused.c.copy(),
            identity(n),
            fused.lower.copy(),
            fused.upper.copy(),
            (),
        )
        return self._solve_osqp(qp, dt)  # the same search has failed already

    def solve(self, qp: QP, dt: float) -> Command:
        """Solve an assembled QP: exactly on an active set reached from the last one, else OSQP.

        OSQP is set up on first use, then updated in place and warm started.

        Args:
            qp: From :meth:`build`.
            dt: Control period [s] (used by the fallback's deceleration).
        """
        if qp.A.shape[0] == qp.c.size:  # bounds only
            found = self._active.search(qp, self.active_set_changes + 1)
            if found is not None:
                self._active, x = found
                self.diagnostics = {"solver": "active set", "relaxed": qp.relaxed}
                return Command(x)
        return self._solve_osqp(qp, dt)

    def _solve_osqp(self, qp: QP, dt: float) -> Command:
        """Solve with OSQP (set up on first use, then updated and warm started)."""
        n = qp.c.size
        bounds_only = qp.A.shape[0] == n
        if self._solver is None or self._solver.rows != qp.A.shape[0]:
            self._solver = _Workspace(qp, self.tolerance, self.max_iterations)
        solved, status, iterations, x, y = self._solver.solve(qp)
        self.diagnostics = {
            "solver": "osqp",
            "status": status,
            "iterations": iterations,
            "relaxed": qp.relaxed,
        }
        if not solved or not np.isfinite(x).all():
            return self._fallback(f"OSQP status {status!r}", dt)
        if bounds_only:  # make the solution exact on the active set OSQP found
            self._active = _ActiveSet.from_multipliers(qp, y, self.tolerance)
            exact = self._active.solve(qp)
            if exact is not None:
                return Command(exact)
        rows = qp.A @ x if qp.A.shape[0] > n else x  # every row, the bounds first
        finite_upper = np.where(np.isfinite(qp.upper), np.abs(qp.upper), 0.0)
        scale = np.maximum(1.0, finite_upper)
        excess = np.maximum(qp.lower - rows, rows - qp.upper) / scale
        if excess.max() > BOUND_TOLERANCE:
            return self._fallback(f"solution leaves its bounds by {excess.max():.3g}", dt)
        return Command(np.clip(x, qp.lower[:n], qp.upper[:n]))  # round-off within tolerance

    def _fallback(self, reason: str, dt: float) -> Command:
        """Bring the last command towards rest at the acceleration limit, within velocity."""
        step = self.limits.acceleration * dt
        qd = np.clip(0.0, self._last - step, self._last + step)
        limit = self.velocity_scale * self.limits.velocity
        qd = np.clip(qd, -limit, limit)
        self.diagnostics["fallback"] = reason
        return Command(qd, f"fallback: {reason}")


class _Workspace:
    """One OSQP problem with a fixed sparsity pattern, updated in place at every step.

    ``H``'s upper triangle and ``A`` are stored dense (every entry structural), so that new
    numbers always fit the pattern OSQP factorised. The updates go straight to OSQP's
    compiled solver when its Python wrapper exposes it (the wrapper re-validates and copies
    on every call, which costs more than the solve of a 7-joint QP); otherwise through the
    wrapper's public ``update``/``solve``.
    """

    def __init__(self, qp: QP, tolerance: float, max_iterations: int) -> None:
        n = qp.c.size
        columns = np.concatenate([np.full(j + 1, j) for j in range(n)])
        rows = np.concatenate([np.arange(j + 1) for j in range(n)])
        self.upper = (rows, columns)  # H's upper triangle in OSQP's column order
        a_rows, a_columns = np.nonzero(np.ones_like(qp.A))
        order = np.lexsort((a_rows, a_columns))  # OSQP stores A column by column
        self.a_index = (a_rows[order], a_columns[order])
        self.rows = qp.A.shape[0]
        P = sparse.csc_matrix((qp.H[self.upper], self.upper), shape=(n, n))
        A = sparse.csc_matrix((qp.A[self.a_index], self.a_index), shape=qp.A.shape)
        self.wrapper = osqp.OSQP()
        self.wrapper.setup(
            P,
            qp.c,
            A,
            *self._finite(qp),
            verbose=False,
            eps_abs=tolerance,
            eps_rel=tolerance,
            max_iter=max_iterations,
            check_termination=5,
            polishing=False,  # replaced by _refine (OSQP skips polishing with no active set)
            warm_starting=True,
        )
        compiled = getattr(self.wrapper, "_solver", None)
        needed = ("update_data_vec", "update_data_mat", "solve", "info", "solution")
        self.compiled = compiled if all(hasattr(compiled, a) for a in needed) else None

    @staticmethod
    def _finite(qp: QP) -> tuple[FloatArray, FloatArray]:
        return np.maximum(qp.lower, -OSQP_INFINITY), np.minimum(qp.upper, OSQP_INFINITY)

    def solve(self, qp: QP) -> tuple[bool, str, int, FloatArray, FloatArray]:
        """Update the numbers, solve from the last solution: (solved, status, iterations, x, y)."""
        px = qp.H[self.upper]
        ax = qp.A[self.a_index] if self.rows > qp.c.size else None
        lower, upper = self._finite(qp)
        if self.compiled is not None:
            self.compiled.update_data_vec(q=qp.c, l=lower, u=upper)
            self.compiled.update_data_mat(P_x=px, P_i=None, A_x=ax, A_i=None)
            self.compiled.solve()
            info = self.compiled.info
            x, y = self.compiled.solution.x, self.compiled.solution.y
        else:
            update: dict[str, Any] = {"Px": px, "q": qp.c, "l": lower, "u": upper}
            if ax is not None:
                update["Ax"] = ax
            self.wrapper.update(**update)
            result = self.wrapper.solve(raise_error=False)
            info, x, y = result.info, result.x, result.y
        solved = int(info.status_val) in USABLE and x is not None
        return solved, str(info.status), int(info.iter), np.array(x), np.array(y)


class _ActiveSet:
    """Which bounds hold as equalities, and the exact QP solution on them.

    Args:
        upper: Joints held at their upper bound, shape (n,) bool.
        lower: Joints held at their lower bound, shape (n,) bool.
    """

    #: Slack of the optimality checks, relative to ``max(1, |c|)``; round-off is far smaller.
    SLACK = 1e-9

    def __init__(self, upper: NDArray[np.bool_], lower: NDArray[np.bool_]) -> None:
        self.upper = upper
        self.lower = lower
        self.fixed = upper | lower
        self.empty = not self.fixed.any()

    @classmethod
    def none(cls, n: int) -> _ActiveSet:
        """No bound held: the unconstrained solution."""
        return cls(np.zeros(n, dtype=bool), np.zeros(n, dtype=bool))

    @classmethod
    def from_multipliers(cls, qp: QP, y: FloatArray, tolerance: float) -> _ActiveSet:
        """The bounds whose OSQP multiplier is clearly non-zero (positive: upper)."""
        n = qp.c.size
        scale = max(1.0, float(np.abs(qp.c).max()))
        return cls(y[:n] > tolerance * scale, y[:n] < -tolerance * scale)

    def solve(self, qp: QP) -> FloatArray | None:
        """The QP's exact solution if this is its active set, else None (bounds-only QPs).

        With the held joints fixed at their bounds the rest is one linear solve. The result
        is the solution only if it meets the optimality conditions: every joint within its
        bounds, and every held joint's cost gradient pointing outwards (a multiplier of the
        right sign). ADMM stops at a tolerance; along weakly weighted directions (a redundant
        arm's self-motion, held only by the damping and posture terms) its ``x`` may be off
        by tolerance / weight, which this removes.
        """
        x = self._on_bounds(qp)
        if x is None or self._next(qp, x) is not self:
            return None
        return np.minimum(np.maximum(x, qp.lower), qp.upper)  # round-off within the slack

    def search(self, qp: QP, tries: int) -> tuple[_ActiveSet, FloatArray] | None:
        """The active set and exact solution reached from this one, or None.

        A primal-dual active-set method for a bounds-only QP: solve with the held joints at
        their bounds; then hold every free joint that left its bounds and release every held
        joint whose multiplier has the wrong sign; repeat until nothing changes, which is
        exactly when the optimality conditions hold. It usually takes one or two changes
        when the active set moved since the last step. None after ``tries`` solves (this set
        and ``tries - 1`` changes), on a cycle or a singular system: let OSQP decide.
        """
        active, seen = self, {self.upper.tobytes() + self.lower.tobytes()}
        for _ in range(tries):
            x = active._on_bounds(qp)
            if x is None:
                return None
            following = active._next(qp, x)
            if following is active:
                return active, np.minimum(np.maximum(x, qp.lower), qp.upper)
            key = following.upper.tobytes() + following.lower.tobytes()
            if key in seen:
                return None
            seen.add(key)
            active = following
        return None

    def _on_bounds(self, qp: QP) -> FloatArray | None:
        """The QP's minimiser with the held joints fixed at their bounds; None if singular."""
        if self.empty:
            _, x, info = lapack.dposv(qp.H, qp.c)
            x = -x
        else:
            K = qp.H.copy()  # the held joints' rows become "x_j = bound"
            K[self.fixed] = 0.0
            K[self.fixed, self.fixed] = 1.0
            rhs = np.where(self.upper, qp.upper, np.where(self.lower, qp.lower, -qp.c))
            _, _, x, info = lapack.dgesv(K, rhs)
        return None if info != 0 else x

    def _next(self, qp: QP, x: FloatArray) -> _ActiveSet:
        """This set if x (its solution) is optimal, else the set to try next.

        Optimal: free joints within their bounds; held joints' cost gradient pointing out of
        the box (at an upper bound no larger than 0, at a lower one no smaller), each up to
        :data:`SLACK` relative to ``max(1, |c|)``. Next: hold the free joints that left, at
        the bound they passed; release the held joints whose gradient points inwards.
        """
        slack = self.SLACK * max(1.0, float(np.abs(qp.c).max()))
        above = x > qp.upper + slack
        below = x < qp.lower - slack
        if self.empty:
            if not (above.any() or below.any()):
                return self
            return _ActiveSet(above, below)
        gradient = qp.H @ x + qp.c
        # A joint whose bounds meet stays held whatever its multiplier's sign (kept as an
        # upper bound), rather than being freed only to be held again at the other one.
        pinned = self.fixed & (qp.lower >= qp.upper)
        upper = above | (self.upper & (gradient <= slack)) | pinned
        lower = (below | (self.lower & (gradient >= -slack))) & ~pinned
        if np.array_equal(upper, self.upper | pinned) and np.array_equal(
            lower, self.lower & ~pinned
        ):
            return self
        return _ActiveSet(upper, lower)


def _checked_rows(constraint: object, n: int) -> Constraint:
    """A user's constraint rows, validated: G (m, n), finite; bounds (m,), lower <= upper."""
    if not isinstance(constraint, Constraint):
        raise InvalidInputError(
            f"constraints must be controllers.Constraint rows, got {type(constraint).__name__}",
            name="constraints",
        )
    G = as_array(constraint.G, "constraint G", (None, n))
    m = G.shape[0]
    bounds = []
    for side, values in (("lower", constraint.lower), ("upper", constraint.upper)):
        array = np.asarray(values, dtype=float)
        if array.shape != (m,) or np.isnan(array).any():
            raise InvalidInputError(
                f"constraint {side} must be {m} numbers (+-inf for none), not NaN; got "
                f"{np.array2string(array, precision=4)}",
                name="constraints",
            )
        bounds.append(array)
    lower, upper = bounds
    bad = np.flatnonzero(lower > upper)
    if bad.size:
        i = int(bad[0])
        raise InvalidInputError(
            f"constraint row {i}: lower {lower[i]:.6g} > upper {upper[i]:.6g}", name="constraints"
        )
    return Constraint(G, lower, upper)
