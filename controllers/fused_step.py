r"""The differential-IK QP step as CasADi functions: the fast path of :class:`DiffIKQP`.

:class:`~controllers.diff_ik_qp.DiffIKQP` builds its QP from small pieces
(:mod:`controllers.qp_terms`), which keeps each term testable but costs many small NumPy
calls per step. :class:`FusedStep` writes the same arithmetic once as a CasADi ``SX``
expression of the measured state and the reference:

1. the tool pose and world-aligned Jacobian (:class:`robots.SymbolicModel`);
2. the Cartesian PID law of :class:`~controllers.cartesian_pid.CartesianPID` (pose error,
   clamped integral, derivative and feed-forward terms);
3. the QP's numbers: ``H`` and ``c`` of the task, damping and posture objectives (the
   posture moving with the velocity given for it), and the velocity, acceleration and
   position boxes intersected in that order;
4. the QP's exact solution with the last step's active set held at its bounds, whether it
   meets the optimality conditions, and the set to try next (:func:`solve_on_set`, the
   symbolic :meth:`ActiveSet.on_bounds` and :meth:`ActiveSet.next_set`).

A second function continues the active-set method from that next set for up to
``active_set_changes`` rounds, unrolled; it runs only when the active set changed. Each is
evaluated in CasADi's virtual machine or, with ``compiled=True``, as C code compiled by the
system's C compiler. Their inputs and outputs are NumPy arrays bound to them once (CasADi's
``Function.buffer``), so a call costs little beyond the arithmetic.

The step covers the usual case only. It reports ``fallback`` when the pieces must decide:
boxes that do not overlap (the pieces relax them in priority order and name them), and, for
the 6-D task, a rotation error within :data:`NEAR_HALF_TURN` of half a turn, where the
rotation axis is ill determined. When the rounds do not settle, the caller hands the numbers
to OSQP.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.controllers.cartesian_pid import AXIS_SINE, CartesianPID
from optraj.controllers.qp_terms import task_weights
from optraj.errors import CompilerError
from optraj.robots import JointLimits, Robot, SymbolicModel

__all__ = ["NEAR_HALF_TURN", "FusedStep", "StepSettings", "solve_on_set"]

FloatArray = NDArray[np.float64]

#: A rotation error within this of pi [rad] goes to the pieces (Pinocchio's ``log3``).
NEAR_HALF_TURN = 1e-3
#: Below this angle [rad] the rotation vector uses the series of ``theta / (2 sin theta)``.
SMALL_ANGLE = 1e-6


@dataclass(frozen=True)
class StepSettings:
    """What a fused step is built from: a :class:`DiffIKQP`'s settings.

    Attributes:
        pid: The Cartesian PID law (gains and task kind are read once).
        weights: Task weights [linear, angular].
        damping: Damping on the joint velocity, > 0.
        posture_weight: Weight of the pull towards the planned joint positions, >= 0.
        posture_gain: Rate of that pull [1/s].
        limits: The limits to respect.
        velocity_scale: Fraction of the velocity limits the command may use.
        position_gain: Fraction of the distance to a position limit one step may cover.
        slack: Relative slack of the optimality test (``ActiveSet.SLACK``).
        changes: Changes of the active set tried after the first solve (0: none).
    """

    pid: CartesianPID
    weights: tuple[float, float]
    damping: float
    posture_weight: float
    posture_gain: float
    limits: JointLimits
    velocity_scale: float
    position_gain: float
    slack: float
    changes: int


class FusedStep:
    """One control step of the differential-IK QP as CasADi functions.

    Args:
        robot: The robot; its tool frame is the task frame.
        settings: The controller's settings.
        compiled: Compile the functions to C with ``compiler`` (once, here) and evaluate
            that; otherwise CasADi's virtual machine evaluates them (slower arithmetic, no
            compiler needed).
        compiler: The C compiler command used when ``compiled``.

    Raises:
        CompilerError: ``compiled`` and the code did not compile (no such compiler, or it
            failed).
        UnsupportedModelError: A joint type that :class:`robots.SymbolicModel` does not
            handle.

    Two functions work on arrays bound to them once, with n = ``robot.dof``:

    * the step: input ``[q (n), qd (n), T_world_tool row by row (16), twist (6), q_ref (n),
      qd_ref (n), integral (6), last command (n), dt]`` and the active set ``[held at
      upper (n), held at lower (n)]`` (1.0 or 0.0); output ``[x (n), ok, fallback,
      integral (6), H column by column (n*n), c (n), lower (n), upper (n), next held at
      upper (n), next held at lower (n)]``;
    * the search (when ``settings.changes`` > 0): input the output from ``H`` on, output
      ``[x (n), ok, held at upper (n), held at lower (n)]`` after up to ``changes`` more
      rounds.
    """

    def __init__(
        self,
        robot: Robot,
        settings: StepSettings,
        compiled: bool = False,
        compiler: str = "gcc",
    ) -> None:
        n = robot.dof
        self.n = n
        self.compiled = compiled
        directory = tempfile.mkdtemp(prefix="optraj-jit-") if compiled else None
        options: dict[str, Any] = {"cse": True}  # common subexpressions evaluated once
        if directory is not None:
            # The C sources and libraries go to a directory of their own, removed as soon as
            # the libraries are loaded (they stay mapped); CasADi is told not to remove them.
            options |= {
                "jit": True,
                "compiler": "shell",
                "jit_cleanup": False,
                "jit_options": {
                    "compiler": compiler,
                    # No fused multiply-adds: the same rounding as NumPy and the virtual
                    # machine, so that ties in the bound and optimality tests break alike.
                    "flags": ["-O2", "-ffp-contract=off"],
                    "directory": directory,
                    "cleanup": False,
                    "verbose": False,
                },
            }
        try:
            step = _step_function(robot, settings, options)
            search = (
                _search_function(n, settings.changes, settings.slack, options)
                if settings.changes > 0
                else None
            )
        except RuntimeError as error:
            if directory is None:
                raise
            lines = str(error).strip().splitlines()
            raise CompilerError(compiler, lines[-1] if lines else "no message") from error
        finally:
            if directory is not None:
                shutil.rmtree(directory, ignore_errors=True)
        self.input = np.zeros(5 * n + 29)
        self.active = np.zeros(2 * n)
        self.output = np.zeros(n * n + 6 * n + 8)
        if step.nnz_out(0) != self.output.size:
            raise RuntimeError("FusedStep's output layout and its function disagree")
        self._step_buffer, self._step = _bind(step, [self.input, self.active], self.output)
        qp = self.output[n + 8 :]  # H, c, bounds and the next set: the search's input
        self.searched = np.zeros(3 * n + 1)
        self._search_buffer: Any = None
        self._search: Callable[[], Any] | None = None
        if search is not None:
            self._search_buffer, self._search = _bind(search, [qp], self.searched)
        # Views into the outputs, valid until the next call.
        out = self.output
        self.x = out[:n]
        self.integral = out[n + 2 : n + 8]
        self.H = qp[: n * n].reshape(n, n, order="F")
        self.c, self.lower, self.upper = (qp[n * n + k * n : n * n + (k + 1) * n] for k in range(3))
        self.searched_x = self.searched[:n]
        self.searched_upper = self.searched[n + 1 : 2 * n + 1]
        self.searched_lower = self.searched[2 * n + 1 :]

    def __getstate__(self) -> dict[str, Any]:
        raise TypeError("FusedStep holds compiled functions; rebuild it in the new process")

    def set_active(self, upper: NDArray[np.bool_], lower: NDArray[np.bool_]) -> None:
        """The joints held at their upper and lower bounds in the next call's exact solve."""
        self.active[: self.n] = upper
        self.active[self.n :] = lower

    def __call__(
        self,
        q: FloatArray,
        qd: FloatArray,
        T_world_tool: FloatArray,
        twist: FloatArray,
        q_ref: FloatArray,
        qd_ref: FloatArray,
        integral: FloatArray,
        last: FloatArray,
        dt: float,
    ) -> tuple[bool, bool]:
        """Evaluate one step: ``(ok, fallback)``; the numbers are in the output views.

        Args:
            q: Measured joint positions [rad or m], shape (n,).
            qd: Measured joint velocities [rad/s or m/s], shape (n,).
            T_world_tool: Planned tool pose, shape (4, 4).
            twist: Planned tool twist [m/s; rad/s], shape (6,).
            q_ref: Posture the QP pulls towards (the planned joint positions), shape (n,).
            qd_ref: Velocity of that posture [rad/s or m/s], shape (n,); zeros for the pull
                towards a posture at rest.
            integral: The PID's integral before the step [m s; rad s], shape (6,).
            last: Last command [rad/s or m/s], shape (n,).
            dt: Control period [s].

        ``ok``: ``x`` is the QP's solution (the active set held). ``fallback``: the numbers
        are not valid for this state; build the step from the pieces.
        """
        np.concatenate(
            (q, qd, T_world_tool.ravel(), twist, q_ref, qd_ref, integral, last, (dt,)),
            out=self.input,
        )
        self._step()
        flags = self.output[self.n : self.n + 2].tolist()
        return flags[0] == 1.0, flags[1] != 0.0

    def search(self) -> bool:
        """After a call that was not ``ok``: change the active set up to ``changes`` times.

        True when an optimal set was reached: ``searched_x`` is the QP's solution and
        ``searched_upper``/``searched_lower`` the set. False without a search function.
        """
        if self._search is None:
            return False
        self._search()
        return bool(self.searched[self.n] == 1.0)


def _bind(
    function: ca.Function, inputs: list[FloatArray], output: FloatArray
) -> tuple[Any, Callable[[], Any]]:
    """``(buffer, call)``: a call of ``function`` that reads ``inputs``, writes ``output``.

    The buffer must be kept as long as the call is used.
    """
    buffer, evaluate = function.buffer()
    for index, array in enumerate(inputs):
        # casadi's stub wants a size; the binding reads it from the (ndarray) buffer itself.
        buffer.set_arg(index, memoryview(array))  # type: ignore[call-arg, arg-type]
    buffer.set_res(0, memoryview(output))  # type: ignore[call-arg, arg-type]
    return buffer, evaluate


def _step_function(robot: Robot, settings: StepSettings, options: dict[str, Any]) -> ca.Function:
    """The step function of :class:`FusedStep` (layout in its docstring)."""
    n = robot.dof
    pid = settings.pid
    packed = ca.SX.sym("input", 5 * n + 29)
    active = ca.SX.sym("active", 2 * n)
    parts = ca.vertsplit(
        packed,
        [0, n, 2 * n, 2 * n + 16, 2 * n + 22, 3 * n + 22, 4 * n + 22, 4 * n + 28, 5 * n + 29],
    )
    q, qd, T_rows, twist_ref, q_ref, qd_ref, integral, tail = parts
    last, dt = tail[:n], tail[n]
    T_ref = ca.reshape(T_rows, 4, 4).T  # the rows arrive one after the other

    symbolic = SymbolicModel(robot)
    T = symbolic.frame_pose(robot.tool_frame_id)(q)
    J = symbolic.frame_jacobian(robot.tool_frame_id)(q)

    # Cartesian PID law (CartesianPID.error and .twist).
    twist, integral, near_half_turn = _pid_twist(pid, T, J, T_ref, twist_ref, qd, integral, dt)

    # Objectives (qp_terms.task_objective, damping_objective, posture_objective).
    W = ca.SX(task_weights(*settings.weights))
    if pid.task == "axis":  # task_weights(axis=...) with the symbolic tool axis
        axis = T[:3, 2]
        W[3:, 3:] = W[3:, 3:] - settings.weights[1] * (axis @ axis.T)
    WJ = W @ J
    H = J.T @ WJ + settings.damping * ca.SX.eye(n)
    c = -(WJ.T @ twist)
    if settings.posture_weight > 0.0:
        H += settings.posture_weight * ca.SX.eye(n)
        c += (settings.posture_weight * settings.posture_gain) * (q - q_ref)
        c -= settings.posture_weight * qd_ref

    # Boxes in priority order (qp_terms.velocity_bounds, acceleration_bounds, position_bounds).
    lower, upper = _boxes(settings, q, last, dt)
    overlap_lost = ca.sum1(lower > upper) > 0

    x, ok, held_upper, held_lower = solve_on_set(
        H, c, lower, upper, active[:n], active[n:], settings.slack
    )
    output = ca.vertcat(
        x,
        ok,
        ca.fmax(overlap_lost, near_half_turn),
        integral,
        ca.vec(H),
        c,
        lower,
        upper,
        held_upper,
        held_lower,
    )
    return ca.Function(
        "diff_ik_qp_step", [packed, active], [output], ["input", "active"], ["output"], options
    )


def _pid_twist(
    pid: CartesianPID,
    T: ca.SX,
    J: ca.SX,
    T_ref: ca.SX,
    twist_ref: ca.SX,
    qd: ca.SX,
    integral: ca.SX,
    dt: ca.SX,
) -> tuple[ca.SX, ca.SX, ca.SX]:
    """The PID law's twist, its new integral and whether the error is near a half turn.

    The same law as ``CartesianPID.error`` and ``.twist``, on symbolic tool pose ``T`` (4, 4),
    Jacobian ``J`` (6, n), planned pose ``T_ref`` and twist ``twist_ref`` [m/s; rad/s].
    """
    linear = T_ref[:3, 3] - T[:3, 3]
    near_half_turn = ca.SX(0)
    if pid.task == "axis":
        z, z_ref = T[:3, 2], T_ref[:3, 2]
        normal = ca.cross(z, z_ref)
        sine = ca.norm_2(normal)
        angle = ca.atan2(sine, ca.dot(z, z_ref))
        angular = ca.if_else(sine > AXIS_SINE, normal * (angle / sine), normal)
    else:
        R_error = T_ref[:3, :3] @ T[:3, :3].T
        vee = ca.vertcat(
            R_error[2, 1] - R_error[1, 2],
            R_error[0, 2] - R_error[2, 0],
            R_error[1, 0] - R_error[0, 1],
        )
        half_sine = ca.norm_2(vee) / 2
        theta = ca.atan2(half_sine, (ca.trace(R_error) - 1) / 2)
        factor = ca.if_else(
            theta < SMALL_ANGLE, 0.5 + theta * theta / 12, theta / (2 * ca.sin(theta))
        )
        angular = factor * vee
        near_half_turn = theta > math.pi - NEAR_HALF_TURN
    error = ca.vertcat(linear, angular)
    kp, ki, kd = (ca.DM(gain) for gain in (pid.kp, pid.ki, pid.kd))
    twist = twist_ref + kp * error
    if pid.ki.any():
        bound = ca.DM(pid.integral_limit)
        integral = ca.fmin(ca.fmax(integral + error * dt, -bound), bound)
        twist += ki * integral
    if pid.kd.any():
        twist += kd * (twist_ref - J @ qd)
    return twist, integral, near_half_turn


def _boxes(settings: StepSettings, q: ca.SX, last: ca.SX, dt: ca.SX) -> tuple[ca.SX, ca.SX]:
    """The joint velocity box ``(lower, upper)``: velocity, acceleration and position limits."""
    limits = settings.limits
    speed = ca.DM(settings.velocity_scale * limits.velocity)
    acceleration = ca.DM(limits.acceleration)
    step = acceleration * dt

    def reach(room: ca.SX) -> ca.SX:
        """Fastest speed towards a limit ``room`` away that still stops short of it."""
        brake = ca.sqrt(step * step + 2 * acceleration * ca.fmax(room, 0)) - step
        return ca.fmin((settings.position_gain / dt) * room, brake)

    lower = ca.fmax(ca.fmax(-speed, last - step), -reach(q - ca.DM(limits.lower)))
    upper = ca.fmin(ca.fmin(speed, last + step), reach(ca.DM(limits.upper) - q))
    return lower, upper


def _search_function(n: int, changes: int, slack: float, options: dict[str, Any]) -> ca.Function:
    """Up to ``changes`` further active sets of a QP (layout in :class:`FusedStep`)."""
    packed = ca.SX.sym("qp", n * n + 5 * n)
    H = ca.reshape(packed[: n * n], n, n)
    c, lower, upper, held_upper, held_lower = ca.vertsplit(
        packed[n * n :], [0, n, 2 * n, 3 * n, 4 * n, 5 * n]
    )
    x, ok = ca.SX.zeros(n), ca.SX(0)
    for _ in range(changes):
        # Once the set is optimal it maps onto itself, so the remaining rounds keep it.
        x, ok, held_upper, held_lower = solve_on_set(
            H, c, lower, upper, held_upper, held_lower, slack
        )
    output = ca.vertcat(x, ok, held_upper, held_lower)
    return ca.Function("diff_ik_qp_search", [packed], [output], ["qp"], ["output"], options)


def solve_on_set(
    H: ca.SX,
    c: ca.SX,
    lower: ca.SX,
    upper: ca.SX,
    held_upper: ca.SX,
    held_lower: ca.SX,
    slack: float,
) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
    """One round of the active-set method on CasADi expressions, for a bounds-only QP.

    The symbolic form of :meth:`ActiveSet.on_bounds` followed by :meth:`ActiveSet.next_set`:
    the exact solution with the held joints at their bounds, written as the symmetric reduced
    system (the free rows and columns of ``H``, unit rows for the held joints), whether it is
    optimal, and the set to try next (this one when optimal, up to its pinned joints).

    Args:
        H: The QP's Hessian, positive definite, shape (n, n).
        c: Its linear term, shape (n, 1).
        lower: Lower bounds of the variables, shape (n, 1).
        upper: Upper bounds of the variables, shape (n, 1).
        held_upper: 1.0 for the joints held at their upper bound, else 0.0, shape (n, 1).
        held_lower: The same for the lower bound.
        slack: Relative slack of the optimality test (:attr:`ActiveSet.SLACK`).

    Returns:
        ``(x, ok, next held at upper, next held at lower)``, masks of 1.0 and 0.0.
    """
    n = c.shape[0]
    held = held_upper + held_lower
    free = 1 - held
    bound = held_upper * upper + held_lower * lower
    rhs = free * -(c + H @ bound) + held * bound
    M = (free @ free.T) * H + ca.diag(held)
    x = _cholesky_solve(M, rhs, n)
    tolerance = slack * ca.fmax(1, ca.mmax(ca.fabs(c)))
    gradient = H @ x + c
    pinned = held * (lower >= upper)  # joints whose bounds meet stay held, at "upper"
    above = x > upper + tolerance
    below = x < lower - tolerance
    next_upper = ca.fmax(ca.fmax(above, held_upper * (gradient <= tolerance)), pinned)
    next_lower = ca.fmax(below, held_lower * (gradient >= -tolerance)) * (1 - pinned)
    same = ca.sum1(
        ca.fabs(next_upper - ca.fmax(held_upper, pinned))
        + ca.fabs(next_lower - held_lower * (1 - pinned))
    )
    finite = ca.sum1(ca.fabs(x) < np.inf) == n
    ok = finite * (same == 0)
    # An optimal set is kept as it is (a pinned joint stays on the side it is held at).
    return x, ok, ca.if_else(ok, held_upper, next_upper), ca.if_else(ok, held_lower, next_lower)


def _cholesky_solve(M: ca.SX, rhs: ca.SX, n: int) -> ca.SX:
    """Solve ``M x = rhs`` for a symmetric positive definite ``M`` by Cholesky, unrolled."""
    L = [[ca.SX(0)] * n for _ in range(n)]
    for j in range(n):
        diagonal = M[j, j] - sum((L[j][k] * L[j][k] for k in range(j)), ca.SX(0))
        L[j][j] = ca.sqrt(diagonal)
        for i in range(j + 1, n):
            off = M[i, j] - sum((L[i][k] * L[j][k] for k in range(j)), ca.SX(0))
            L[i][j] = off / L[j][j]
    y = [ca.SX(0)] * n
    for i in range(n):
        y[i] = (rhs[i] - sum((L[i][k] * y[k] for k in range(i)), ca.SX(0))) / L[i][i]
    x = [ca.SX(0)] * n
    for i in reversed(range(n)):
        x[i] = (y[i] - sum((L[k][i] * x[k] for k in range(i + 1, n)), ca.SX(0))) / L[i][i]
    return ca.vertcat(*x)
