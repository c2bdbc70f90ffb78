r"""Multiple-shooting transcription of a multi-phase joint motion into a CasADi NLP.

The motion is split into phases (e.g. approach, strike, stop), phase :math:`p` into
:math:`N_p` intervals. Each interval length :math:`h_k` is a decision variable: fixed by its
bounds in a phase of fixed duration, free in a free phase (so that jerk switches can fall on
nodes; a small cost keeps neighbours alike, or with ``free_grid=False`` rows make them
equal). The state at every node is
:math:`x_k = (q_k, \dot q_k, \ddot q_k)`; the jerk :math:`u_k` is constant on interval
:math:`k`, so the motion is a cubic on each interval and a step is the exact
triple-integrator map

.. math::

    q_{k+1} &= q_k + h \dot q_k + \tfrac{h^2}{2} \ddot q_k + \tfrac{h^3}{6} u_k \\
    \dot q_{k+1} &= \dot q_k + h \ddot q_k + \tfrac{h^2}{2} u_k \\
    \ddot q_{k+1} &= \ddot q_k + h u_k

imposed as equality constraints (multiple shooting). States and jerks are scaled by their
limits (positions by the half range about the middle of the range), durations are in
seconds.

Limits hold everywhere, not only at the nodes: acceleration is linear and jerk constant on
an interval, so node bounds suffice for them; velocity (quadratic) and position (cubic) are
bounded by the Bernstein coefficients of their polynomials on each interval, which bound the
polynomial from both sides (convex-hull property). The position rows (two per interval and
joint, a third of all rows) can be left out (``position_rows=False``): positions are then
bounded at the nodes only, and the planner checks them between nodes. Torques are
constrained at chosen nodes only; the planner verifies them between nodes. Their rows are
either the symbolic RNEA itself (``torque_rows="rnea"``) or its first-order expansion about
given node states (``"linear"``): rows linear in the node state whose coefficients are NLP
parameters (:func:`torque_linearization`), so they add nothing to the Hessian and one
compiled NLP serves every expansion point. The planner expands again about each solution
until the dense torques hold; at a fixed point the rows equal the RNEA rows to first order,
so the solution satisfies the same optimality conditions.

Task rows:

* a strike phase (pool cue): at every node the tool origin is on the schedule
  :math:`p_{entry} + v\,t\,d` and the tool z axis has no component along two unit vectors
  :math:`e_1, e_2` perpendicular to :math:`d` (with :math:`d \cdot z \ge 0`), so the roll
  stays free; the tool velocity equals :math:`v d` at the window's entry and exit only
  (the positions on the schedule fix the speed in between; equalities at every node would
  over-determine a 7-DOF arm whose last joint only rolls the cue);
* a contact node (paddle): the velocity of a point ``offset`` along the tool z axis equals a
  given vector.

Fixed boundary states, via points and the contact configuration are variable bounds, so one
compiled NLP serves every problem with the same :class:`Structure`; the strike line and the
contact velocity are NLP parameters (:data:`PARAMETERS`).
"""

from __future__ import annotations

import contextlib
import functools
import math
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import UnknownNameError
from optraj.robots import JointLimits, SymbolicModel
from optraj.validation import as_choice, as_vector, ndim_of

__all__ = [
    "PARAMETERS",
    "TORQUE_ROWS",
    "CompiledNLP",
    "FrozenOptions",
    "Layout",
    "Rows",
    "Structure",
    "compile_nlp",
    "deadline",
    "freeze_options",
    "jerk_step",
    "parameter_vector",
    "stop_callback",
    "strike_node_rows",
    "structure_limits",
    "thaw_options",
    "time_left",
    "torque_linearization",
    "torque_parameter_count",
]

#: Ways of writing the torque rows (module docstring).
TORQUE_ROWS = ("rnea", "linear")
#: Most IPOPT iterations of a warm-started solve. Warm solves of the strike benchmark's shots
#: whose ball moved 2 cm take 3 to 34 iterations (median 9); the few that take longer start
#: from an active set far from the new problem's, and took 300 to 630 iterations at the
#: warm start's small barrier parameter where a solve from the same primal point with a fresh
#: barrier takes about 60.
WARM_ITERATIONS = 50

FloatArray = NDArray[np.float64]

#: NLP parameters, name and size, in order.
PARAMETERS: tuple[tuple[str, int], ...] = (
    ("time_scale", 1),  # [s] divides every cost term so that the objective is O(1)
    ("entry", 3),  # strike line entry point [m]
    ("direction", 3),  # strike direction d [-]
    ("e1", 3),  # unit vectors perpendicular to d [-]
    ("e2", 3),
    ("speed", 1),  # strike speed [m/s]
    ("contact_velocity", 3),  # required velocity of the contact point [m/s]
    ("offset", 1),  # contact point offset along tool z [m]
)


def parameter_vector(**values: Any) -> FloatArray:
    """The parameter vector of :data:`PARAMETERS`; missing entries are zero (time_scale 1).

    Raises:
        UnknownNameError: A name that is not one of :data:`PARAMETERS`.
        InvalidInputError: A value that is not a finite number or vector of its size.
    """
    known = [name for name, _ in PARAMETERS]
    unknown = sorted(set(values) - set(known))
    if unknown:
        raise UnknownNameError("NLP parameter", unknown[0], known)
    parts = []
    for name, size in PARAMETERS:
        default = 1.0 if name == "time_scale" else 0.0
        value = values.get(name, np.full(size, default))
        parts.append(as_vector(np.reshape(value, -1) if ndim_of(value) == 0 else value, name, size))
    return np.concatenate(parts)


#: The deadline of the solver calls made on each thread, as a ``time.perf_counter()`` value
#: [s]; absent (no deadline) outside :func:`deadline`.
_DEADLINE = threading.local()


@contextlib.contextmanager
def deadline(seconds: float) -> Iterator[None]:
    """Solver calls on this thread inside the block stop ``seconds`` [s] from now.

    A solver built with :func:`stop_callback` asks its solver to stop at the first iteration
    past the deadline (IPOPT then returns ``User_Requested_Stop``); :func:`time_left` tells
    the caller how much is left. Nested blocks keep the earlier deadline; ``math.inf`` sets
    none.
    """
    previous = getattr(_DEADLINE, "at", math.inf)
    _DEADLINE.at = min(previous, time.perf_counter() + seconds)
    try:
        yield
    finally:
        _DEADLINE.at = previous


def time_left() -> float:
    """Seconds until this thread's :func:`deadline` [s]; ``math.inf`` without one."""
    return getattr(_DEADLINE, "at", math.inf) - time.perf_counter()


class _Stop(ca.Callback):  # type: ignore[misc]
    """An NLP solver's iteration callback: nonzero (stop) once the thread's deadline passed."""

    def __init__(self, variables: int, constraints: int, parameters: int) -> None:
        ca.Callback.__init__(self)
        self._sizes = {
            "x": variables,
            "lam_x": variables,
            "g": constraints,
            "lam_g": constraints,
            "lam_p": parameters,
            "f": 1,
        }
        self.construct("optraj_deadline", {})

    def get_n_in(self) -> int:
        return int(ca.nlpsol_n_out())

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return str(ca.nlpsol_out(i))

    def get_name_out(self, i: int) -> str:
        return "stop"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(self._sizes.get(ca.nlpsol_out(i), 0), 1)

    def eval(self, arg: Sequence[Any]) -> list[float]:
        return [1.0 if time_left() <= 0.0 else 0.0]


def stop_callback(variables: int, constraints: int, parameters: int) -> ca.Callback:
    """An ``iteration_callback`` for ``casadi.nlpsol`` that stops the solve at the deadline.

    The solver keeps a reference only: the caller must keep the returned object alive as
    long as the solver.

    Args:
        variables: Decision variables of the NLP.
        constraints: Constraint rows.
        parameters: Parameters.
    """
    return _Stop(variables, constraints, parameters)


def jerk_step(h: Any, q: Any, v: Any, a: Any, u: Any) -> tuple[Any, Any, Any]:
    """Position, velocity and acceleration after ``h`` [s] at constant jerk ``u``.

    The exact triple-integrator step of the transcription, for NumPy arrays and CasADi
    expressions alike: the NLP's dynamics rows, the solution's integration and the guess fit
    all take it from here.
    """
    return (
        q + h * v + h**2 / 2 * a + h**3 / 6 * u,
        v + h * a + h**2 / 2 * u,
        a + h * u,
    )


@dataclass(frozen=True)
class Structure:
    """Everything that shapes the NLP; equal structures share one compiled solver.

    Attributes:
        robot: The robot's :attr:`~robots.Robot.fingerprint` (with ``limits`` it identifies
            the constants in the NLP).
        limits: Limit rows (lower, upper, velocity, acceleration, jerk, effort) as tuples.
        tool_frame: Frame whose pose the task rows constrain.
        intervals: Intervals per phase.
        free: Per phase, whether its duration is a decision (else fixed by bounds).
        strike_phase: Index of the strike phase, or -1.
        contact_node: Node of the contact velocity rows, or -1.
        position_rows: Whether positions are bounded between nodes (Bernstein rows) or at
            the nodes only.
        torque_nodes: Nodes with torque rows.
        torque_rows: ``"rnea"`` (the symbolic inverse dynamics) or ``"linear"`` (its
            expansion, coefficients as parameters after :data:`PARAMETERS`).
        weights: Objective weights as ``(term, weight)`` pairs (time, jerk, effort, posture).
        margin: Fraction of the velocity, acceleration and jerk limits kept free [-].
        torque_margin: Fraction of the torque limits kept free at torque nodes [-] (RNEA
            rows; linear rows take it in their coefficients).
        solver: CasADi NLP plugin name.
        options: Solver options as sorted ``(key, value)`` pairs.
    """

    robot: str
    limits: tuple[tuple[float, ...], ...]
    tool_frame: str
    intervals: tuple[int, ...]
    free: tuple[bool, ...]
    free_grid: bool = True
    strike_phase: int = -1
    contact_node: int = -1
    position_rows: bool = True
    torque_nodes: tuple[int, ...] = ()
    torque_rows: str = "rnea"
    weights: tuple[tuple[str, float], ...] = (("time", 1.0),)
    margin: float = 0.0
    torque_margin: float = 0.0
    solver: str = "ipopt"
    options: tuple[tuple[str, Any], ...] = ()


class Layout:
    """Where each quantity sits in the decision vector ``w``.

    ``w = [h_0 .. h_{K-1}, x_0 .. x_K, u_0 .. u_{K-1}]``: interval lengths [s], scaled node
    states ``(zq, zv, za)`` (3n each) and scaled jerks (n each).

    Args:
        n: Joint count.
        intervals: Intervals per phase.
    """

    def __init__(self, n: int, intervals: Sequence[int]) -> None:
        self.n = n
        self.intervals = tuple(int(i) for i in intervals)
        self.phases = len(self.intervals)
        self.K = sum(self.intervals)
        self.nodes = self.K + 1
        self.x_start = self.K
        self.u_start = self.x_start + 3 * n * self.nodes
        self.size = self.u_start + n * self.K
        #: Phase of each interval, shape (K,).
        self.phase_of = np.repeat(np.arange(self.phases), self.intervals)
        #: First node of each phase, shape (P + 1,) (the last entry is K).
        self.first_node = np.concatenate([[0], np.cumsum(self.intervals)]).astype(int)

    def x_index(self, node: int, block: int) -> slice:
        """Indices of block 0 (zq), 1 (zv) or 2 (za) of a node's state."""
        start = self.x_start + 3 * self.n * node + block * self.n
        return slice(start, start + self.n)

    def u_index(self, interval: int) -> slice:
        """Indices of an interval's scaled jerk."""
        start = self.u_start + self.n * interval
        return slice(start, start + self.n)

    def split(self, w: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(h, X, U)``: interval lengths (K,), scaled states (K + 1, 3n), jerks (K, n)."""
        durations = w[: self.K]
        states = w[self.x_start : self.u_start].reshape(self.nodes, 3 * self.n)
        jerks = w[self.u_start :].reshape(self.K, self.n)
        return durations, states, jerks


@dataclass
class CompiledNLP:
    """A CasADi NLP and its solver, built once per :class:`Structure`.

    Attributes:
        structure: What it was built for.
        layout: Decision vector layout.
        w: Decision variables (SX).
        p: Parameters (SX), see :data:`PARAMETERS`.
        f: Objective (SX).
        g: Constraints (SX).
        lbg: Lower constraint bounds, shape (m,).
        ubg: Upper constraint bounds, shape (m,).
        groups: ``(name, first row, end row)`` of each constraint group in ``g``.
        scale: Physical scales ``(mid, half, velocity, acceleration, jerk)``, each (n,).
        solver: ``nlpsol`` for cold starts.
        constraint_values: ``(w, p) -> g``, to measure a solution's violations.
        torque_expansion: ``z (3n, m) -> (t (n, m), J (n, 3n m))``: the torques over the
            effort limits at m scaled node states and their Jacobians, for linear torque
            rows (None without them).
        row_joint: Joint index of each row of ``g``, -1 for a row of no one joint (the
            strike line's), shape (m,).
        row_part: Which part of a joint's state a row is about (0 position, 1 velocity,
            2 acceleration; the dynamics rows' step of that part), shape (m,).
        row_at: The interval (dynamics and between-node rows) or node (torque, strike
            rows) of each row, -1 for none, shape (m,).
        stopper: The solvers' iteration callback (:func:`stop_callback`), kept alive here.
        lock: Serialises calls of the solvers.
    """

    structure: Structure
    layout: Layout
    w: ca.SX
    p: ca.SX
    f: ca.SX
    g: ca.SX
    lbg: FloatArray
    ubg: FloatArray
    groups: tuple[tuple[str, int, int], ...]
    scale: tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]
    solver: ca.Function
    constraint_values: ca.Function
    torque_expansion: ca.Function | None = None
    warm_solver: ca.Function | None = None
    row_joint: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, np.intp))
    row_part: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, np.intp))
    row_at: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, np.intp))
    stopper: ca.Callback | None = None
    lock: threading.Lock = field(default_factory=threading.Lock)

    @functools.cached_property
    def group_order(self) -> tuple[tuple[str, ...], NDArray[np.intp], NDArray[np.intp]]:
        """``(names, order, starts)``: the rows of ``g`` gathered by group.

        ``names`` in order of first appearance; ``g[order]`` lists the rows of ``names[0]``
        first, from ``starts[0]``, then those of ``names[1]``, and so on, so a reduction per
        group is one ``reduceat``.
        """
        names = tuple(dict.fromkeys(name for name, first, end in self.groups if end > first))
        pieces = [
            np.concatenate([np.arange(a, b) for n, a, b in self.groups if n == name])
            for name in names
        ]
        sizes = [piece.size for piece in pieces]
        order = np.concatenate(pieces).astype(np.intp) if pieces else np.zeros(0, np.intp)
        starts = np.cumsum([0, *sizes[:-1]]).astype(np.intp)
        return names, order, starts

    def warm(self) -> ca.Function:
        """The solver set up for warm starts (primal and dual), built on first use."""
        if self.warm_solver is None:
            options = dict(self.structure.options)
            if self.structure.solver == "ipopt":
                options["ipopt.warm_start_init_point"] = "yes"
                options["ipopt.warm_start_bound_push"] = 1e-9
                options["ipopt.warm_start_mult_bound_push"] = 1e-9
                # The barrier starts where a cold solve's stopping test leaves it (IPOPT
                # stops once the barrier problem is solved to barrier_tol_factor = 10 times
                # the barrier parameter): a tenth of the tolerance, 1e-7 at IPOPT's own 1e-6.
                # From a solution to 1e-4, a start at 1e-7 took 380 iterations over 20 warm
                # strike re-plans against 216 from solutions to 1e-6.
                options["ipopt.mu_init"] = 0.1 * float(options.get("ipopt.tol", 1e-6))
                # A warm solve that has not converged by then is dropped for a cold one from
                # the same primal point (OptimalControl._solve).
                options["ipopt.max_iter"] = min(
                    int(options.get("ipopt.max_iter", WARM_ITERATIONS)), WARM_ITERATIONS
                )
            self.warm_solver = _nlpsol(self, options)
        return self.warm_solver


class FrozenOptions(tuple):  # type: ignore[type-arg]
    """A solver option mapping as sorted ``(key, value)`` pairs, hashable for a Structure."""

    __slots__ = ()


def freeze_options(value: Any) -> Any:
    """``value`` with every mapping a :class:`FrozenOptions` and every list a tuple."""
    if isinstance(value, dict):
        return FrozenOptions(sorted((str(k), freeze_options(v)) for k, v in value.items()))
    if isinstance(value, list):
        return tuple(freeze_options(v) for v in value)
    return value


def thaw_options(value: Any) -> Any:
    """The inverse of :func:`freeze_options` (tuples stay tuples; CasADi takes them)."""
    if isinstance(value, FrozenOptions):
        return {k: thaw_options(v) for k, v in value}
    if isinstance(value, tuple):
        return tuple(thaw_options(v) for v in value)
    return value


def _nlpsol(compiled: CompiledNLP, options: dict[str, Any]) -> ca.Function:
    nlp = {"x": compiled.w, "p": compiled.p, "f": compiled.f, "g": compiled.g}
    thawed = {k: thaw_options(v) for k, v in options.items()}
    if compiled.stopper is None:
        compiled.stopper = stop_callback(
            int(compiled.w.numel()), int(compiled.g.numel()), int(compiled.p.numel())
        )
    thawed.setdefault("iteration_callback", compiled.stopper)
    return ca.nlpsol("optraj_ocp", compiled.structure.solver, nlp, thawed)


class Rows:
    """Constraint rows collected group by group, each labelled with its joint and place."""

    def __init__(self) -> None:
        self.rows: list[ca.SX] = []
        self.lower: list[FloatArray] = []
        self.upper: list[FloatArray] = []
        self.groups: list[tuple[str, int, int]] = []
        self.joint: list[NDArray[np.intp]] = []
        self.part: list[NDArray[np.intp]] = []
        self.at: list[NDArray[np.intp]] = []
        self.count = 0

    def add(
        self,
        name: str,
        expr: ca.SX,
        lower: float | FloatArray,
        upper: float | FloatArray,
        *,
        joints: int = 0,
        parts: Sequence[int] = (),
        at: int = -1,
    ) -> None:
        """Rows ``lower <= expr <= upper`` (bounds broadcast), in group ``name``.

        Args:
            name: The group.
            expr: The row expressions (any shape; taken column by column).
            lower: Lower bounds, broadcast to the rows.
            upper: Upper bounds, broadcast to the rows.
            joints: With n > 0, the rows come in blocks of one row per joint (row i is
                joint ``i % n``'s); 0 for rows of no one joint.
            parts: The state part of each block (0 position, 1 velocity, 2 acceleration),
                one entry per block; none given: -1.
            at: The interval or node the rows belong to, -1 for none.
        """
        size = int(expr.numel())
        if size == 0:
            return
        self.rows.append(ca.vec(expr))
        self.lower.append(np.broadcast_to(np.asarray(lower, float).reshape(-1), (size,)))
        self.upper.append(np.broadcast_to(np.asarray(upper, float).reshape(-1), (size,)))
        index = np.arange(size, dtype=np.intp)
        self.joint.append(index % joints if joints else np.full(size, -1, np.intp))
        blocks = index // joints if joints else index
        part = np.asarray(parts, dtype=np.intp)
        self.part.append(part[blocks] if part.size else np.full(size, -1, np.intp))
        self.at.append(np.full(size, at, np.intp))
        if self.groups and self.groups[-1][0] == name and self.groups[-1][2] == self.count:
            self.groups[-1] = (name, self.groups[-1][1], self.count + size)
        else:
            self.groups.append((name, self.count, self.count + size))
        self.count += size


def structure_limits(limits: JointLimits) -> tuple[tuple[float, ...], ...]:
    """Limit rows of a :class:`Structure`: lower, upper, velocity, acceleration, jerk, effort."""
    return tuple(
        tuple(float(v) for v in values)
        for values in (
            limits.lower,
            limits.upper,
            limits.velocity,
            limits.acceleration,
            limits.jerk,
            limits.effort,
        )
    )


def torque_parameter_count(structure: Structure) -> int:
    """Parameters of the linear torque rows, after :data:`PARAMETERS` (0 for RNEA rows)."""
    if structure.torque_rows != "linear":
        return 0
    n = len(structure.limits[0])
    return len(structure.torque_nodes) * (n + 3 * n * n)


def torque_linearization(
    compiled: CompiledNLP, w: FloatArray, margin: float | FloatArray
) -> FloatArray:
    """Coefficients of linear torque rows, expanded about the node states of ``w``.

    The row of a torque node is ``c + B z`` with ``z = (zq, zv, za)`` its scaled state,
    bounded by [-1, 1]: at the expansion point it equals the RNEA torque over
    ``(1 - margin)`` times the effort limit, and its gradient is the RNEA's.

    Args:
        compiled: An NLP with linear torque rows.
        w: Decision vector whose node states are the expansion points.
        margin: Fraction of the torque limits kept free [-]: one for every row, or one per
            torque node and joint, shape (nodes, n).

    Returns:
        Parameter values, shape (:func:`torque_parameter_count`,): per torque node ``c``
        then ``B`` (n x 3n) in column order.
    """
    structure, layout = compiled.structure, compiled.layout
    nodes = structure.torque_nodes
    if compiled.torque_expansion is None or not nodes:
        return np.zeros(0)
    n = layout.n
    _, states, _ = layout.split(np.asarray(w, dtype=float))
    z = states[list(nodes)].T  # (3n, m)
    t, jac = (np.asarray(v) for v in compiled.torque_expansion(z))
    # The mapped Jacobians sit side by side, (n, 3n m): node i's in columns 3n i .. 3n (i + 1).
    jac = jac.reshape(n, 3 * n, len(nodes), order="F").transpose(2, 0, 1)  # (m, n, 3n)
    scale = np.broadcast_to(1.0 / (1.0 - np.asarray(margin, dtype=float)), (len(nodes), n))
    c = scale * (t.T - np.einsum("mij,jm->mi", jac, z))
    b = scale[:, :, None] * jac
    blocks = [np.concatenate([c[i], b[i].reshape(-1, order="F")]) for i in range(len(nodes))]
    return np.concatenate(blocks)


def compile_nlp(structure: Structure, symbolic: SymbolicModel) -> CompiledNLP:
    """Build the NLP of ``structure`` (fully expanded SX) and its solver.

    Args:
        structure: The NLP's shape and constants.
        symbolic: Symbolic kinematics and dynamics of the robot.

    Returns:
        The compiled NLP.
    """
    lower, upper, vel, acc, jerk, effort = (np.asarray(r) for r in structure.limits)
    n = lower.size
    layout = Layout(n, structure.intervals)
    mid, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
    as_choice(structure.torque_rows, "torque rows", TORQUE_ROWS)
    w = ca.SX.sym("w", layout.size)
    base = sum(size for _, size in PARAMETERS)
    p = ca.SX.sym("p", base + torque_parameter_count(structure))
    params: dict[str, ca.SX] = {}
    offset = 0
    for name, size in PARAMETERS:
        params[name] = p[offset : offset + size]
        offset += size

    h = [w[k] for k in range(layout.K)]

    def physical(z: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX]:
        """(q, qd, qdd) of a scaled node state ``z = (zq, zv, za)``."""
        return mid + half * z[:n], vel * z[n : 2 * n], acc * z[2 * n :]

    def node_state(node: int) -> ca.SX:
        return w[layout.x_index(node, 0).start : layout.x_index(node, 2).stop]

    def state(node: int) -> tuple[ca.SX, ca.SX, ca.SX]:
        return physical(node_state(node))

    rows = Rows()
    keep = 1.0 - structure.margin
    weights = dict(structure.weights)
    time_scale = params["time_scale"]
    cost = ca.SX(0.0)
    for k in range(layout.K):
        phase = int(layout.phase_of[k])
        if structure.free[phase] and weights.get("time", 0.0):
            cost += weights["time"] * h[k] / time_scale
        if structure.free[phase] and k + 1 < layout.K and int(layout.phase_of[k + 1]) == phase:
            if not structure.free_grid:
                rows.add("uniform grid", h[k + 1] - h[k], 0.0, 0.0)
            elif weights.get("grid", 0.0):
                cost += weights["grid"] * layout.K * ((h[k + 1] - h[k]) / time_scale) ** 2

    rnea = symbolic.rnea()
    for k in range(layout.K):
        hk = h[k]
        q0, v0, a0 = state(k)
        q1, v1, a1 = state(k + 1)
        zu = w[layout.u_index(k)]
        u = jerk * zu
        q_next, v_next, a_next = jerk_step(hk, q0, v0, a0, u)
        rows.add(
            "dynamics",
            ca.vertcat((q1 - q_next) / half, (v1 - v_next) / vel, (a1 - a_next) / acc),
            0.0,
            0.0,
            joints=n,
            parts=(0, 1, 2),
            at=k,
        )
        rows.add(
            "velocity between nodes",
            (v0 + hk / 2 * a0) / vel,
            -keep,
            keep,
            joints=n,
            parts=(1,),
            at=k,
        )
        if structure.position_rows:
            rows.add(
                "position between nodes",
                ca.vertcat((q0 + hk / 3 * v0 - mid) / half, (q1 - hk / 3 * v1 - mid) / half),
                -1.0,
                1.0,
                joints=n,
                parts=(0, 0),
                at=k,
            )
        if weights.get("jerk", 0.0):
            cost += weights["jerk"] * hk * ca.sumsqr(zu) / (n * time_scale)
        if weights.get("posture", 0.0):
            cost += weights["posture"] * hk * ca.sumsqr((q0 - mid) / half) / (n * time_scale)
        if weights.get("effort", 0.0):
            tau = rnea(q0, v0, a0) / effort
            cost += weights["effort"] * hk * ca.sumsqr(tau) / (n * time_scale)

    if structure.strike_phase >= 0:
        _strike_rows(rows, structure, layout, symbolic, params, h, state)
    if structure.contact_node >= 0:
        _contact_rows(rows, structure, symbolic, params, state)
    expansion = None
    if structure.torque_rows == "linear":
        size = n + 3 * n * n
        for i, node in enumerate(structure.torque_nodes):
            block = p[base + i * size : base + (i + 1) * size]
            z = node_state(node)
            row = block[:n] + ca.reshape(block[n:], n, 3 * n) @ z
            rows.add("torque", row, -1.0, 1.0, joints=n, at=node)
        if structure.torque_nodes:
            z = ca.SX.sym("z", 3 * n)
            t = rnea(*physical(z)) / effort
            single = ca.Function("torque_expansion", [z], [t, ca.jacobian(t, z)])
            expansion = single.map(len(structure.torque_nodes))
    else:
        for node in structure.torque_nodes:
            tau = rnea(*state(node)) / effort
            limit = 1.0 - structure.torque_margin
            rows.add("torque", tau, -limit, limit, joints=n, at=node)

    g = ca.vertcat(*rows.rows)
    compiled = CompiledNLP(
        structure=structure,
        layout=layout,
        w=w,
        p=p,
        f=cost,
        g=g,
        lbg=np.concatenate(rows.lower),
        ubg=np.concatenate(rows.upper),
        groups=tuple(rows.groups),
        scale=(mid, half, vel, acc, jerk),
        solver=None,  # type: ignore[arg-type]
        constraint_values=ca.Function("constraint_values", [w, p], [g]),
        torque_expansion=expansion,
        row_joint=np.concatenate(rows.joint),
        row_part=np.concatenate(rows.part),
        row_at=np.concatenate(rows.at),
    )
    compiled.solver = _nlpsol(compiled, dict(structure.options))
    return compiled


def _strike_rows(
    rows: Rows,
    structure: Structure,
    layout: Layout,
    symbolic: SymbolicModel,
    params: dict[str, ca.SX],
    h: list[ca.SX],
    state: Any,
) -> None:
    """Cue tip on the schedule, cue axis on the line at every node; speed at entry and exit."""
    ph = structure.strike_phase
    tool = (
        symbolic.frame_position(structure.tool_frame),
        symbolic.frame_rotation(structure.tool_frame),
        symbolic.frame_jacobian(structure.tool_frame),
    )
    entry, d = params["entry"], params["direction"]
    first, last = int(layout.first_node[ph]), int(layout.first_node[ph + 1])
    for j, node in enumerate(range(first, last + 1)):
        q, qd, _ = state(node)
        target = entry + params["speed"] * ca.sum1(ca.vertcat(0, *h[first : first + j])) * d
        strike_node_rows(rows, tool, params, q, qd, target, node in (first, last), node)


def strike_node_rows(
    rows: Rows,
    tool: tuple[ca.Function, ca.Function, ca.Function],
    params: dict[str, ca.SX],
    q: ca.SX,
    qd: ca.SX,
    target: ca.SX,
    at_end: bool,
    node: int = -1,
) -> None:
    """The strike line's rows at one node, shared by the NLP and the window check.

    The cue tip at ``target`` [m], the cue axis along the direction (its two components across
    it zero, and pointing forward), and at the window's ends (``at_end``) the tip velocity
    ``speed * direction`` [m/s].

    Args:
        rows: The rows to add to.
        tool: The tool frame's position, rotation and Jacobian as functions of q.
        params: ``direction``, ``e1``, ``e2`` (the unit vectors across it) and ``speed``.
        q: Joint positions [rad or m].
        qd: Joint velocities [rad/s or m/s].
        target: The tip's place on the schedule [m].
        at_end: Whether the node is the window's first or last.
        node: The node's index, to label the rows with (-1: none).
    """
    position, rotation, jacobian = tool
    d, e1, e2 = params["direction"], params["e1"], params["e2"]
    rows.add("strike position", position(q) - target, 0.0, 0.0, at=node)
    z = rotation(q)[:, 2]
    rows.add("strike axis", ca.vertcat(ca.dot(e1, z), ca.dot(e2, z)), 0.0, 0.0, at=node)
    rows.add("strike axis sign", ca.dot(d, z), 0.0, np.inf, at=node)
    if at_end:
        speed = jacobian(q)[:3, :] @ qd - params["speed"] * d
        rows.add("strike speed", speed, 0.0, 0.0, at=node)


def _contact_rows(
    rows: Rows,
    structure: Structure,
    symbolic: SymbolicModel,
    params: dict[str, ca.SX],
    state: Any,
) -> None:
    """Velocity of the contact point (``offset`` along tool z) at the contact node."""
    rotation = symbolic.frame_rotation(structure.tool_frame)
    jacobian = symbolic.frame_jacobian(structure.tool_frame)
    q, qd, _ = state(structure.contact_node)
    jac = jacobian(q)
    lever = params["offset"] * rotation(q)[:, 2]
    twist = jac @ qd
    velocity = twist[:3] + ca.cross(twist[3:], lever)
    rows.add("contact velocity", velocity - params["contact_velocity"], 0.0, 0.0)
