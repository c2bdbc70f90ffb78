"""Refinement rounds of a plan: solves repeated with tighter bounds and rows until they hold."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InfeasibleError,
    SolverError,
)
from optraj.planners.ocp.options import (
    GRID_WEIGHT,
    MAX_STRIKE_INTERVALS,
    POSITION_SHRINKS,
    ROUNDS,
    STRIKE_GRID_WEIGHT,
    TORQUE_POINTS,
    TORQUE_WATCH,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.refinement import (
    fixed_ratios,
    position_excess,
    shrunk,
    tightened,
)
from optraj.planners.ocp.solution import (
    dense_times,
    with_totals,
)
from optraj.planners.trajectory import Trajectory

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]


def round_weights(
    planner: OptimalControl, spec: Spec, *, time_only: bool = False
) -> dict[str, float]:
    """The objective weights of a round, with the regularization terms added."""
    weights = {"time": 1.0} if time_only else dict(planner.weights)
    robot = spec.robot
    if set(weights) == {"time"} and all(d is not None for d in spec.durations):
        weights = {"jerk": 1.0}  # nothing to shorten: the smoothest motion in the time
    if planner.regularization > 0.0:
        weights["jerk"] = weights.get("jerk", 0.0) + planner.regularization
        weights["grid"] = GRID_WEIGHT if spec.strike_phase < 0 else STRIKE_GRID_WEIGHT
        if robot.dof >= 7:
            weights["posture"] = planner.regularization
    return weights


def solve_rounds(
    planner: OptimalControl,
    problem: Any,
    spec: Spec,
    weights: dict[str, float],
    warm_start: Trajectory | None,
) -> Trajectory:
    """Solve ``spec`` in rounds, adding torque and position rows and finer grids until they hold."""
    torque_nodes: tuple[int, ...] = ()
    position_rows = planner.position_rows is True
    shrink: FloatArray | None = None  # node bounds moved in, (nodes, 2, n) [rad or m]
    shrinks = 0
    strike_scale = 1
    saved = None if warm_start is None else warm_start.metadata.get("warm_start")
    if isinstance(saved, WarmStart) and len(saved.structure.intervals) == len(spec.names):
        # Same grid and torque rows as the previous solution, so its duals apply too.
        spec.intervals = saved.structure.intervals
        torque_nodes = saved.structure.torque_nodes
        position_rows = position_rows or saved.structure.position_rows
    torque_margin = planner.torque_margin
    row_margins: FloatArray | None = None  # linear rows: per node and joint
    expansions = 0  # rounds in a row solved with linear rows
    solves: list[Trajectory] = []
    for round_ in range(1, ROUNDS + 1):
        built = planner._build(
            problem,
            spec,
            weights,
            torque_nodes,
            strike_scale,
            warm_start,
            torque_margin,
            row_margins,
            position_rows,
            shrink,
        )
        traj = planner._solve(built)
        solves.append(traj)
        # Nothing but the grid to change: no torque rows, no moved bounds, no new rows.
        plain = not built.compiled.structure.torque_nodes and shrink is None
        ratios = planner._torque_ratios(traj, spec)
        more = [] if planner.torque is False else planner._torque_nodes(traj, ratios, built, spec)
        misses = planner._strike_misses(traj, problem, spec)
        strike_ok = not misses
        excess = None if position_rows else position_excess(traj, spec.limits)
        positions_ok = excess is None or not excess.any()
        if not more and strike_ok and positions_ok:
            with_totals(traj, solves)
            traj.metadata["rounds"] = round_
            traj.metadata["torque_rows"] = len(built.compiled.structure.torque_nodes)
            traj.metadata["position_rows"] = position_rows
            return traj
        if not positions_ok and shrinks < POSITION_SHRINKS:
            # A piece passed a limit between nodes: its nodes' bounds move in, warm.
            shrink = shrunk(shrink, excess, spec.limits)
            shrinks += 1
        elif not positions_ok:  # it does not settle: rows from now on
            position_rows, shrink = True, None
        if not strike_ok:  # a finer strike grid renumbers the nodes
            strike_intervals = built.compiled.structure.intervals[spec.strike_phase]
            if strike_intervals >= MAX_STRIKE_INTERVALS and plain and positions_ok:
                break  # no finer grid, and nothing else that a new round would drop
            strike_scale *= 2
            torque_nodes, row_margins, expansions = (), None, 0
            shrink, shrinks = None, 0
        elif more and ratios is not None:
            rows = built.compiled.structure.torque_nodes
            if planner.torque_rows == "linear":
                # Rows at every node: the next round expands about this solution. From
                # the second expansion about a solution with rows on, rows whose torques
                # still break the limit (at or between their nodes) keep more room, so
                # that rounds which swap the binding nodes back and forth settle.
                expansions = expansions + 1 if rows else 0
                if expansions >= 2:
                    if row_margins is None:
                        row_margins = np.full((len(rows), spec.limits.n), torque_margin)
                    row_margins = tightened(
                        row_margins, ratios[2] / spec.limits.effort, fixed_ratios(spec)
                    )
            elif set(more) <= set(rows):  # rows everywhere needed: keep more room
                torque_margin = min(0.2, 2.0 * torque_margin + 0.01)
            torque_nodes = tuple(sorted(set(torque_nodes) | set(more)))
        warm_start = traj
    torque_rows = built.compiled.structure.torque_nodes
    if torque_rows and ratios is not None and ratios[1].max() > 1.0:
        tau = ratios[2]
        i, j = np.unravel_index(int(np.argmax(np.abs(tau) / spec.limits.effort)), tau.shape)
        joint, value = spec.limits.names[j], float(tau[i, j])
        limit = float(spec.limits.effort[j])
        raise InfeasibleError(
            f"torque of {joint} stays at {value:.4g} N m (limit {limit:.4g}) after "
            f"{round_} rounds, the last with torque rows at {len(torque_rows)} nodes",
            limit="effort",
            joint=joint,
            required=value,
            allowed=limit,
        )
    if not misses:
        unsettled = "position limits" if not positions_ok else "torque rows"
        raise SolverError(
            planner.solver, f"{unsettled} not settled", detail=f"after {round_} rounds"
        )
    what = "; ".join(
        f"{name} {value:.3g} {unit} (plans keep it within {allowed:.3g} {unit}, half the tolerance)"
        for name, value, allowed, unit in misses
    )
    if ratios is not None and ratios[1].max() > 1.0:
        what += f"; torques up to {ratios[1].max():.3g} of their limits"
    intervals = built.compiled.structure.intervals[spec.strike_phase]
    raise SolverError(
        planner.solver,
        "strike line not met between nodes",
        detail=f"with {intervals} strike intervals after {round_} rounds: {what}; a looser "
        f"tolerance or a faster strike (a shorter window) may pass",
    )


def torque_ratios(traj: Trajectory, spec: Spec) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """Torques at TORQUE_POINTS per interval: (times, worst |tau| / effort, tau).

    None when the effort limits are not all finite (nothing to watch).
    """
    effort = spec.limits.effort
    if not np.all(np.isfinite(effort)):
        return None
    times = dense_times(traj, TORQUE_POINTS)
    s = traj.sample(times)
    tau = spec.robot.inverse_dynamics(s.q, s.qd, s.qdd)
    return times, np.max(np.abs(tau) / effort, axis=1), tau


def torque_nodes(
    planner: OptimalControl,
    traj: Trajectory,
    ratios: tuple[FloatArray, FloatArray, FloatArray] | None,
    built: OptimalControlProblem,
    spec: Spec,
) -> list[int]:
    """Nodes to add torque rows at: around intervals where a torque nears its limit.

    None once every torque keeps within ``1 - torque_margin / 2`` of its limit, or within
    what a fixed state of the problem itself needs of that joint's limit, if more (a
    start holding 99 % of a limit against gravity: :func:`fixed_room`).
    """
    if ratios is None:
        return []
    times, ratio, tau = ratios
    settled = np.maximum(1.0 - 0.5 * planner.torque_margin, fixed_ratios(spec))
    if np.all(np.abs(tau) / spec.limits.effort <= settled):
        return []
    knots = traj.breakpoints
    hot = np.unique(
        np.clip(np.searchsorted(knots, times[ratio > TORQUE_WATCH], "right") - 1, 0, len(knots) - 2)
    )
    nodes: set[int] = set()
    for k in hot.tolist():
        nodes.update((k, k + 1))
    existing = set(built.compiled.structure.torque_nodes)
    return sorted(nodes - existing) or sorted(nodes)


def strike_misses(
    planner: OptimalControl, traj: Trajectory, problem: Any, spec: Spec
) -> list[tuple[str, float, float, str]]:
    """Where the cue tip leaves its schedule between the strike nodes.

    Returns:
        ``(what, worst, allowed, unit)`` for each of the distance to the schedule [mm],
        the cue axis's angle to the direction [deg] and the relative speed error [%]
        that passes half its tolerance; empty when the strike stays on schedule.
    """
    if spec.strike_phase < 0:
        return []
    phase = traj.phase("strike")
    knots = traj.breakpoints
    inside = knots[(knots >= phase.t_start - 1e-12) & (knots <= phase.t_end + 1e-12)]
    fractions = np.array([0.25, 0.5, 0.75])
    times = (inside[:-1, None] + fractions[None, :] * np.diff(inside)[:, None]).reshape(-1)
    s = traj.sample(times)
    robot = spec.robot
    poses = robot.tool_pose(s.q)
    direction = np.asarray(problem.direction)
    speed = float(problem.speed)
    schedule = problem.entry_point + speed * (times - phase.t_start)[:, None] * direction
    gap = np.max(np.linalg.norm(poses[:, :3, 3] - schedule, axis=1))
    axis = np.clip(poses[:, :3, 2] @ direction, -1.0, 1.0)
    angle = np.max(np.arccos(axis))
    jac = robot.jacobian(s.q)
    velocity = np.einsum("kij,kj->ki", jac[:, :3, :], s.qd)
    speed_error = np.max(np.linalg.norm(velocity - speed * direction, axis=1)) / speed
    measured = (
        ("distance to the schedule", 1e3 * gap, 1e3 * problem.position_tolerance, "mm"),
        ("cue axis angle", np.degrees(angle), np.degrees(problem.angle_tolerance), "deg"),
        ("speed error", 100 * speed_error, 100 * problem.speed_tolerance, "%"),
    )
    return [
        (name, float(value), 0.5 * float(tolerance), unit)
        for name, value, tolerance, unit in measured
        if not value <= 0.5 * tolerance
    ]
