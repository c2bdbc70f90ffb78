r"""Multiple-shooting transcription of a multi-phase joint motion into a CasADi NLP.

The motion is split into phases (e.g. approach, strike, stop), phase :math:`p` into
:math:`N_p` intervals. Each interval length :math:`h_k` is a decision variable: fixed by its
bounds in a phase of fixed duration, free in a free phase (so that jerk switches can fall on
nodes; a small cost keeps neighbours alike, or each near its length in the first point, or
with ``free_grid=False`` rows make them equal). The state at every node is
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

Task rows (:mod:`planners.ocp.task_rows`), after the rows above and before the torque rows,
each kind built from a constraint of the problem:

* a strike line (pool cue, :class:`planners.ocp.task_rows.strike_line.StrikeLineRows`): at
  every node of its window the tool origin on the schedule and the tool z axis on the line;
  the tool velocity at the window's entry and exit;
* a tool contact (paddle, :class:`planners.ocp.task_rows.tool_contact.ToolContactRows`): the
  velocity of a point ``offset`` along the tool z axis at the contact node;
* a pool strike's clearance (:class:`planners.ocp.task_rows.clearance.ClearanceRows`):
  spheres on the cue (and wrist) above the cloth at every node, the cue tip behind the ball
  at the approach's nodes.

Fixed boundary states, via points and the contact configuration are variable bounds, so one
compiled NLP serves every problem with the same :class:`Structure`; the task rows' numbers
are named NLP parameters (:class:`planners.ocp.parameters.ParameterLayout`).
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.budget import (
    deadline,
    stop_callback,
    time_left,
)
from optraj.planners.ocp.parameters import ParameterLayout
from optraj.planners.ocp.rows import (
    Rows,
    structure_limits,
    torque_linearization,
    torque_parameter_count,
)
from optraj.planners.ocp.structure import (
    TORQUE_ROWS,
    Layout,
    Structure,
    jerk_step,
)
from optraj.planners.ocp.task_rows import TaskContext, strike_node_rows
from optraj.robots import SymbolicModel
from optraj.validation import as_choice

__all__ = [
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
    "stop_callback",
    "strike_node_rows",
    "structure_limits",
    "thaw_options",
    "time_left",
    "torque_linearization",
    "torque_parameter_count",
]
#: Most IPOPT iterations of a warm-started solve. A warm solve that needs more starts from an
#: active set far from the new problem's, where the warm start's small barrier parameter
#: makes slow progress: a solve from the same primal point with a fresh barrier is quicker.
WARM_ITERATIONS = 50

FloatArray = NDArray[np.float64]


@dataclass
class CompiledNLP:
    """A CasADi NLP and its solver, built once per :class:`Structure`.

    Attributes:
        structure: What it was built for.
        layout: Decision vector layout.
        w: Decision variables (SX).
        p: Parameters (SX), laid out by ``parameters``.
        f: Objective (SX).
        g: Constraints (SX).
        lbg: Lower constraint bounds, shape (m,).
        ubg: Upper constraint bounds, shape (m,).
        groups: ``(name, first row, end row)`` of each constraint group in ``g``.
        scale: Physical scales ``(mid, half, velocity, acceleration, jerk)``, each (n,).
        solver: ``nlpsol`` for cold starts.
        constraint_values: ``(w, p) -> g``, to measure a solution's violations.
        parameters: The named parameters in ``p``, laid out from the structure's task rows.
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
    parameters: ParameterLayout
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
                options["ipopt.mu_init"] = 0.1 * float(options.get("ipopt.tol", 1e-6))
                # A warm solve that has not converged by then is dropped for a cold one from
                # the same primal point (OptimalControl._solve).
                options["ipopt.max_iter"] = min(
                    int(options.get("ipopt.max_iter", WARM_ITERATIONS)), WARM_ITERATIONS
                )
            self.warm_solver = _nlpsol(self, options)
        return self.warm_solver


class FrozenOptions(tuple):
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


@dataclass(frozen=True)
class _Nodes:
    """The decision vector's node states in physical units (scaled by ``mid``, ``half``...)."""

    w: ca.SX
    layout: Layout
    mid: ca.DM
    half: ca.DM
    vel: ca.DM
    acc: ca.DM

    def physical(self, z: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX]:
        """(q, qd, qdd) of a scaled node state ``z = (zq, zv, za)``."""
        n = self.layout.n
        q: Any = self.mid + self.half * z[:n]
        qd: Any = self.vel * z[n : 2 * n]
        qdd: Any = self.acc * z[2 * n :]
        return q, qd, qdd

    def node_state(self, node: int) -> ca.SX:
        """The scaled state ``(zq, zv, za)`` of ``node``, shape (3 n,)."""
        return self.w[self.layout.x_index(node, 0).start : self.layout.x_index(node, 2).stop]

    def state(self, node: int) -> tuple[ca.SX, ca.SX, ca.SX]:
        """(q, qd, qdd) of ``node``."""
        return self.physical(self.node_state(node))


def _grid_terms(
    rows: Rows,
    structure: Structure,
    layout: Layout,
    h: list[ca.SX],
    params: dict[str, ca.SX],
) -> ca.SX:
    """The time and grid cost terms; uniform-grid rows when a free grid is not allowed.

    The grid term either keeps neighbouring intervals of a free phase alike (weight
    ``grid``) or keeps each near its length in the first point, the parameter ``anchor``
    [s] (weight ``anchor``: a first point whose nodes already sit on the jerk switches of
    the move's slowest joint, :func:`planners.ocp.guesses.switch_times`). The anchored term
    is convex in the interval lengths alone, so the solver's steps stay near that grid.
    """
    weights = dict(structure.weights)
    time_scale = params["time_scale"]
    cost = ca.SX(0.0)
    for k in range(layout.K):
        phase = int(layout.phase_of[k])
        if structure.free[phase] and weights.get("time", 0.0):
            cost += weights["time"] * h[k] / time_scale
        if structure.free[phase] and weights.get("anchor", 0.0):
            cost += weights["anchor"] * layout.K * ((h[k] - params["anchor"][k]) / time_scale) ** 2
        if structure.free[phase] and k + 1 < layout.K and int(layout.phase_of[k + 1]) == phase:
            if not structure.free_grid:
                rows.add("uniform grid", h[k + 1] - h[k], 0.0, 0.0)
            elif weights.get("grid", 0.0):
                cost += weights["grid"] * layout.K * ((h[k + 1] - h[k]) / time_scale) ** 2
    return cost


def _interval_terms(
    rows: Rows,
    structure: Structure,
    nodes: _Nodes,
    h: list[ca.SX],
    scales: tuple[ca.DM, ca.DM, ca.SX],
    rnea: Callable[[], ca.Function],
    cost: ca.SX,
) -> ca.SX:
    """Each interval's dynamics and between-node rows, and ``cost`` plus its integral terms.

    ``scales`` holds the jerk and effort limits and the objective's time scale; ``rnea``
    returns the symbolic inverse dynamics (built on first use: only the effort term needs it).
    """
    jerk, effort, time_scale = scales
    layout, mid, half, vel, acc = nodes.layout, nodes.mid, nodes.half, nodes.vel, nodes.acc
    n = layout.n
    keep = 1.0 - structure.margin
    weights = dict(structure.weights)
    for k in range(layout.K):
        hk = h[k]
        q0, v0, a0 = nodes.state(k)
        q1, v1, a1 = nodes.state(k + 1)
        zu = nodes.w[layout.u_index(k)]
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
            tau = rnea()(q0, v0, a0) / effort
            cost += weights["effort"] * hk * ca.sumsqr(tau) / (n * time_scale)
    return cost


def _torque_terms(
    rows: Rows,
    structure: Structure,
    nodes: _Nodes,
    coefficients: ca.SX,
    rnea: Callable[[], ca.Function],
    effort: ca.DM,
) -> ca.Function | None:
    """The torque rows at the structure's torque nodes; the mapped expansion of linear ones.

    The linear rows' coefficients are ``coefficients``, the parameter ``torque``; ``rnea``
    returns the symbolic inverse dynamics, called only when there are torque nodes.
    """
    n = nodes.layout.n
    expansion = None
    if structure.torque_rows == "linear":
        size = n + 3 * n * n
        for i, node in enumerate(structure.torque_nodes):
            block = coefficients[i * size : (i + 1) * size]
            z = nodes.node_state(node)
            row = block[:n] + ca.reshape(block[n:], n, 3 * n) @ z
            rows.add("torque", row, -1.0, 1.0, joints=n, at=node)
        if structure.torque_nodes:
            z = ca.SX.sym("z", 3 * n)
            t = rnea()(*nodes.physical(z)) / effort
            single = ca.Function("torque_expansion", [z], [t, ca.jacobian(t, z)])
            expansion = single.map(len(structure.torque_nodes))
    else:
        for node in structure.torque_nodes:
            tau = rnea()(*nodes.state(node)) / effort
            limit = 1.0 - structure.torque_margin
            rows.add("torque", tau, -limit, limit, joints=n, at=node)
    return expansion


def _parameter_layout(structure: Structure) -> ParameterLayout:
    """The named parameters of the NLP of ``structure``, in order.

    ``time_scale`` [s] (the objective's divisor, which keeps it about 1), the parameters of
    each of its task rows, ``torque`` (the linear torque rows' coefficients, none for
    RNEA rows: :func:`torque_parameter_count`) and, with an ``anchor`` weight, ``anchor``
    (the interval lengths the grid term keeps near [s]).
    """
    entries = [("time_scale", 1)]
    for task in structure.tasks:
        entries.extend(task.parameters)
    entries.append(("torque", torque_parameter_count(structure)))
    if dict(structure.weights).get("anchor", 0.0):
        entries.append(("anchor", sum(structure.intervals)))  # [s], one per interval
    return ParameterLayout(entries)


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
    parameters = _parameter_layout(structure)
    p = ca.SX.sym("p", parameters.size)
    params = parameters.symbols(p)

    h = [w[k] for k in range(layout.K)]
    # Constants as CasADi matrices: NumPy arrays would reach each SX operation through
    # NumPy's operator dispatch, slower by far when the graph is built (same graph).
    nodes = _Nodes(w, layout, ca.DM(mid), ca.DM(half), ca.DM(vel), ca.DM(acc))
    jerk_dm, effort_dm = ca.DM(jerk), ca.DM(effort)
    rows = Rows()
    time_scale = params["time_scale"]
    cost = _grid_terms(rows, structure, layout, h, params)
    # The symbolic RNEA (the costliest expression to build) only when a term needs it.
    rnea = symbolic.rnea
    cost = _interval_terms(rows, structure, nodes, h, (jerk_dm, effort_dm, time_scale), rnea, cost)
    task = TaskContext(symbolic, structure.tool_frame, layout, h, params, nodes.state)
    for task_rows in structure.tasks:
        task_rows.add(rows, task)
    expansion = _torque_terms(rows, structure, nodes, params["torque"], rnea, effort_dm)

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
        solver=None,  # type: ignore[arg-type]  # set below: nlpsol reads the compiled NLP
        constraint_values=ca.Function("constraint_values", [w, p], [g]),
        parameters=parameters,
        torque_expansion=expansion,
        row_joint=np.concatenate(rows.joint),
        row_part=np.concatenate(rows.part),
        row_at=np.concatenate(rows.at),
    )
    compiled.solver = _nlpsol(compiled, dict(structure.options))
    return compiled
