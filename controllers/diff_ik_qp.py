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
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.active_set import ActiveSet
from optraj.controllers.cartesian_pid import CartesianPID, tool_kinematics
from optraj.controllers.controller import Command, Controller, Reference, State
from optraj.controllers.fused_step import FusedStep, StepSettings

# OSQP_INFINITY and USABLE belong to the workspace; re-exported, importable from here too.
from optraj.controllers.osqp_workspace import OSQP_INFINITY, USABLE, OSQPWorkspace  # noqa: F401
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
            C with gcc (once, when the controller is made or unpickled; its steps are then
            faster); ``"pieces"``, :meth:`build` from
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
        self._solver: OSQPWorkspace | None = None
        self._last = np.zeros(robot.dof)
        self._rest = np.zeros(robot.dof)  # the posture's velocity without posture_velocity
        self._active = ActiveSet.none(robot.dof)
        self._fused: FusedStep | None = None
        self._fused_active: ActiveSet | None = None  # the set FusedStep holds
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
        return FusedStep(self.robot, self.step_settings(), compiled=compiled)

    def step_settings(self) -> StepSettings:
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
            ActiveSet.SLACK,
            self.active_set_changes,
        )

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "differential-IK QP"

    @property
    def active_set(self) -> ActiveSet:
        """The bounds that held at the last step's solution, where the next step starts."""
        return self._active

    def reset(self, state: State) -> None:
        """Clear the integral and the warm start; the measured velocity becomes the last command."""
        self.pid.reset()
        self._solver = None
        self._last = np.array(state.qd, dtype=float)
        self._active = ActiveSet.none(self.robot.dof)
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
            self._active = ActiveSet(fused.searched_upper > 0.5, fused.searched_lower > 0.5)
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
            self._solver = OSQPWorkspace(qp, self.tolerance, self.max_iterations)
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
            self._active = ActiveSet.from_multipliers(qp, y, self.tolerance)
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
