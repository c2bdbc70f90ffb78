"""Reading a solver's point: the trajectory, its integrability, totals and a failure's diagnosis."""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    OptrajError,
    SolverError,
)
from optraj.planners.ocp.options import (
    FIT_JERK_WEIGHT,
    KEPT_NODE_WEIGHT,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
)
from optraj.planners.ocp.transcription import (
    Layout,
    jerk_step,
)
from optraj.planners.profiles.time_scaling import quintic_coefficients
from optraj.planners.trajectory import Phase, Trajectory

FloatArray = NDArray[np.float64]


#: Names of the state parts the rows of :class:`planners.ocp.transcription.CompiledNLP` label.
_PARTS = ("position", "velocity", "acceleration")
#: A limit counts as binding at a solver's point when it uses this fraction of its bound [-].
BINDING = 0.995


def diagnosis(built: OptimalControlProblem, w: FloatArray) -> str:
    """What a failed solve's point breaks and which joint limits it presses, in words.

    The most violated row, with its joint, its part (position, velocity or acceleration
    step of the dynamics rows) and its interval or node in its phase; then the joint limits
    the point holds at :data:`BINDING` or more of their bounds (velocity, acceleration and
    jerk from the scaled node states and jerks, torques by the robot's inverse dynamics at
    the nodes), the most used first. An infeasible NLP's point is where the solver found
    the violation least: the limits it presses are the ones that keep the rows from being
    met.
    """
    compiled, layout = built.compiled, built.compiled.layout
    names = built.problem.limits.names
    g = np.asarray(compiled.constraint_values(w, built.p)).reshape(-1)
    excess = np.maximum(compiled.lbg - g, g - compiled.ubg)
    bound_excess = float(np.max(np.maximum(built.lbx - w, w - built.ubx), initial=0.0))
    row = int(np.argmax(excess)) if excess.size else -1
    if row < 0 or bound_excess > excess[row]:
        worst = f"the variable bounds by {bound_excess:.3g} (scaled)"
    else:
        group = next(name for name, a, b in compiled.groups if a <= row < b)
        joint, part = int(compiled.row_joint[row]), int(compiled.row_part[row])
        at = int(compiled.row_at[row])
        what = group
        if group == "dynamics" and part >= 0:
            what += f" (the {_PARTS[part]} step)"
        if joint >= 0:
            what += f" of {names[joint]}"
        if at >= 0:
            interval = group in ("dynamics", "velocity between nodes", "position between nodes")
            phase = int(layout.phase_of[min(at, layout.K - 1)])
            first = int(layout.first_node[phase])
            kind = "interval" if interval else "node"
            what += f" at {kind} {at - first} of the {built.grids[phase].name} phase"
        worst = f"{what} by {float(excess[row]):.3g} (scaled)"
    mid, half, vel, acc, _ = compiled.scale
    _, states, jerks = layout.split(w)
    n = layout.n
    keep = 1.0 - compiled.structure.margin
    use = {
        "velocity": np.abs(states[:, n : 2 * n]).max(axis=0) / keep,
        "acceleration": np.abs(states[:, 2 * n :]).max(axis=0) / keep,
        "jerk": np.abs(jerks).max(axis=0, initial=0.0) / keep,
    }
    effort = np.asarray(compiled.structure.limits[5])
    try:
        tau = built.problem.robot.inverse_dynamics(
            mid + half * states[:, :n], vel * states[:, n : 2 * n], acc * states[:, 2 * n :]
        )
        use["torque"] = np.abs(tau).max(axis=0) / effort
    except OptrajError:  # pragma: no cover - a point too far out for the dynamics
        pass
    pressed = sorted(
        (
            (float(ratio[j]), names[j], quantity)
            for quantity, ratio in use.items()
            for j in range(n)
            if ratio[j] >= BINDING
        ),
        reverse=True,
    )
    if not pressed:
        return f"most violated: {worst}; no joint limit is at its bound at the solver's point"
    listed = ", ".join(
        f"{joint} {quantity} at {ratio:.3g} of its limit" for ratio, joint, quantity in pressed[:4]
    )
    more = f" and {len(pressed) - 4} more" if len(pressed) > 4 else ""
    return f"most violated: {worst}; binding at the solver's point: {listed}{more}"


def casadi_reason(message: str) -> str:
    """The reason in a CasADi error message, without its call chain and source locations.

    Its first two lines after the ``Error in Function::call ...`` lines.
    """
    lines = [
        re.sub(r"^\S*\.(?:cpp|hpp):\d+:\s*", "", line.strip())
        for line in message.splitlines()
        if line.strip() and not line.strip().startswith("Error in Function::call")
    ]
    return " ".join(lines[:2]) or message.strip()


@dataclass(frozen=True)
class SolverCall:
    """One call of a compiled solver (:meth:`OptimalControl._call`)."""

    w: FloatArray  # primal solution, scaled (empty when the solver raised)
    result: dict[str, Any]  # the solver's outputs
    stats: dict[str, Any]  # the solver's statistics
    wall: float  # [s]
    worst: float  # violation of the most violated constraint group (scaled)
    error: SolverError | None  # why the call failed, or None

    def spent(self) -> tuple[int, float, float]:
        """Iterations, wall time [s] and function evaluation time [s] of the call."""
        iterations = max(int(self.stats.get("iter_count", 0)), 0)
        return iterations, self.wall, evaluation_time(self.stats)


def with_totals(traj: Trajectory, solves: list[Trajectory]) -> Trajectory:
    """Solve statistics of ``traj`` summed over ``solves`` (its own last among them).

    ``iterations``, ``nlp_time`` and ``evaluation_time`` [s] count every solve a plan made;
    ``warm_started`` tells whether the first started from multipliers; ``round_iterations``
    lists them.
    """
    rounds = [
        count
        for t in solves
        for count in t.metadata.get("round_iterations", [int(t.metadata["iterations"])])
    ]
    last = traj.metadata
    last["round_iterations"] = rounds
    last["iterations"] = sum(rounds)
    for key in ("nlp_time", "evaluation_time"):
        last[key] = sum(float(t.metadata[key]) for t in solves)
    last["warm_started"] = bool(solves[0].metadata["warm_started"])
    return traj


def evaluation_time(stats: Mapping[str, Any]) -> float:
    """Wall time [s] a CasADi solver spent evaluating the NLP's functions and derivatives.

    The sum of the solver's ``t_wall_nlp_*`` statistics (objective, constraints, their
    gradients and Jacobian, the Lagrangian's Hessian); the rest of a solve's time is the
    solver's own (for IPOPT mostly its sparse linear algebra).
    """
    return float(
        sum(float(v) for k, v in stats.items() if k.startswith("t_wall_nlp_") and v is not None)
    )


def dense_times(traj: Trajectory, per_interval: int) -> FloatArray:
    """``per_interval`` equally spaced times in each interval of ``traj``, and its end [s]."""
    knots = traj.breakpoints
    fractions = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
    inner = knots[:-1, None] + fractions[None, :] * np.diff(knots)[:, None]
    return np.append(inner.reshape(-1), knots[-1])


def integrable(
    w: FloatArray,
    layout: Layout,
    scale: tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray],
    kept: list[int],
) -> FloatArray:
    """The node states and jerks nearest those of ``w`` that meet the dynamics rows exactly.

    A guess sampled at the nodes breaks the triple-integrator rows wherever its jerk is not
    constant over an interval (a Ruckig move switches jerk between nodes), and IPOPT spends
    its first iterations repairing them. Per
    joint, with the interval lengths of ``w``, the node states are linear in the first state
    and the interval jerks; those are fitted by least squares to the sampled states, in the
    NLP's scaling, with the ``kept`` nodes (phase ends, the strike line) weighted
    :data:`KEPT_NODE_WEIGHT` and the jerks :data:`FIT_JERK_WEIGHT`.
    """
    mid, half, velocity, acceleration, jerk = scale
    n, count = layout.n, layout.K
    h, states, _ = layout.split(w)
    # Rows of the node positions, velocities and accelerations in (q0, v0, a0, u_0 .. u_K-1).
    to_q = np.zeros((count + 1, count + 3))
    to_v = np.zeros((count + 1, count + 3))
    to_a = np.zeros((count + 1, count + 3))
    to_q[0, 0] = to_v[0, 1] = to_a[0, 2] = 1.0
    jerk_rows = np.eye(count + 3)[3:]  # jerk k's coefficient row
    for k in range(count):
        to_q[k + 1], to_v[k + 1], to_a[k + 1] = jerk_step(
            h[k], to_q[k], to_v[k], to_a[k], jerk_rows[k]
        )
    weight = np.ones(count + 1)
    weight[kept] = KEPT_NODE_WEIGHT
    square = weight[:, None] ** 2
    grams = [rows.T @ (square * rows) for rows in (to_q, to_v, to_a)]
    jerk_gram = np.diag(np.r_[np.zeros(3), np.ones(count)])
    targets = (
        states[:, :n] * half + mid,
        states[:, n : 2 * n] * velocity,
        states[:, 2 * n :] * acceleration,
    )
    # Per joint, the normal equations of the least-squares fit, each quantity in the NLP's
    # scaling (over its half range or limit); the joints are solved side by side.
    scales = np.stack([half, velocity, acceleration])  # (3, n)
    normal = np.einsum("sn,sij->nij", scales**-2.0, np.stack(grams))
    normal += (FIT_JERK_WEIGHT / jerk)[:, None, None] ** 2 * jerk_gram
    right = sum(
        (rows.T @ (square * target)) / scale**2
        for rows, target, scale in zip((to_q, to_v, to_a), targets, scales, strict=True)
    )
    z = np.linalg.solve(normal, right.T[:, :, None])[:, :, 0].T  # (count + 3, n)
    fitted_states = np.hstack(
        [(to_q @ z - mid) / half, to_v @ z / velocity, to_a @ z / acceleration]
    )
    fitted_jerks = z[3:] / jerk
    fitted = w.copy()
    fitted[layout.x_start : layout.u_start] = fitted_states.reshape(-1)
    fitted[layout.u_start :] = fitted_jerks.reshape(-1)
    return fitted


def solution_trajectory(built: OptimalControlProblem, w: FloatArray) -> Trajectory:
    """The solution as piecewise quintics, ending on the last node's state.

    Its jerks are integrated exactly from the first node. The solver meets the integration
    rows only to its tolerance, so the integrated end drifts from the last node by up to a
    few 1e-9 (a joint whose goal is on its limit ended 4e-9 m past it): one quintic over
    the whole motion, starting at zero at rest, closes the gap. Its jerk, about 60 times
    the drift over the duration cubed, is far below any jerk limit.
    """
    compiled = built.compiled
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    durations, states, jerks = layout.split(w)
    n = layout.n
    q = mid + half * states[0, :n]
    v = vel * states[0, n : 2 * n]
    a = acc * states[0, 2 * n :]
    coefficients = np.zeros((layout.K, 6, n))
    knots = np.zeros(layout.K + 1)
    for k in range(layout.K):
        h = durations[k]
        u = jerk * jerks[k]
        coefficients[k, :4] = (q, v, a / 2.0, u / 6.0)
        q, v, a = jerk_step(h, q, v, a, u)
        knots[k + 1] = knots[k] + h
    end = states[layout.K]
    coefficients += end_correction(
        knots,
        mid + half * end[:n] - q,
        vel * end[n : 2 * n] - v,
        acc * end[2 * n :] - a,
    )
    phases = [
        Phase(grid.name, float(knots[layout.first_node[i]]), float(knots[layout.first_node[i + 1]]))
        for i, grid in enumerate(built.grids)
    ]
    names = built.problem.limits.names
    return Trajectory(knots, coefficients, joint_names=names, phases=phases, metadata={})


def end_correction(knots: FloatArray, dq: FloatArray, dv: FloatArray, da: FloatArray) -> FloatArray:
    """Local coefficients, shape (K, 6, n), of one quintic over all of ``knots``.

    It starts at zero at rest and ends at (``dq``, ``dv``, ``da``) [rad or m, /s, /s^2].
    """
    # c(t) = g3 t^3 + g4 t^4 + g5 t^5: the quintic from rest at zero to (dq, dv, da) at T
    g3, g4, g5 = quintic_coefficients(np.zeros_like(dq), dq, float(knots[-1]), 0.0, dv, 0.0, da)[3:]
    t = knots[:-1, None]
    # Taylor coefficients c^(j)(t_k) / j! at each segment's start.
    return np.stack(
        [
            g3 * t**3 + g4 * t**4 + g5 * t**5,
            3.0 * g3 * t**2 + 4.0 * g4 * t**3 + 5.0 * g5 * t**4,
            3.0 * g3 * t + 6.0 * g4 * t**2 + 10.0 * g5 * t**3,
            g3 + 4.0 * g4 * t + 10.0 * g5 * t**2,
            g4 + 5.0 * g5 * t,
            np.broadcast_to(g5, (t.size, g5.size)),
        ],
        axis=1,
    )
