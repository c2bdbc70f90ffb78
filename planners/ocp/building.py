"""The NLP of a spec: phase grids, solver options, compiled structures and the first point."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InvalidInputError,
)
from optraj.planners.compiled_cache import ProcessCache
from optraj.planners.ocp.guesses import switch_times
from optraj.planners.ocp.options import (
    CLOSE_MU_INIT,
    MAX_PHASE_INTERVALS,
    MAX_STRIKE_INTERVALS,
    MIN_INTERVAL,
    STRIKE_MU_INIT,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
    PhaseGrid,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.refinement import (
    constraint_duals,
    fixed_room,
    strike_caps,
)
from optraj.planners.ocp.solution import (
    casadi_reason,
    integrable,
)
from optraj.planners.ocp.transcription import (
    CompiledNLP,
    Layout,
    Structure,
    compile_nlp,
    freeze_options,
    structure_limits,
    torque_linearization,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import Robot, SymbolicModel

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]

#: Compiled NLPs by structure, shared by every planner object of the process: building one
#: takes longer than most solves with it. The least recently used is dropped past the size.
COMPILED: ProcessCache[CompiledNLP] = ProcessCache(64)
#: Symbolic robot models by robot fingerprint, shared the same way.
MODELS: ProcessCache[SymbolicModel] = ProcessCache(16)


def forget_compiled() -> None:
    """Drop every compiled NLP and symbolic model the process shares.

    Frees their memory; the next plan of each shape builds its NLP again (planner objects
    keep the NLPs they already used). Benchmarks call it to time a first plan.
    """
    COMPILED.clear()
    MODELS.clear()


def phase_grids(planner: OptimalControl, spec: Spec, strike_scale: int) -> tuple[PhaseGrid, ...]:
    """The time grid of each phase of ``spec``, strike windows ``strike_scale`` times finer."""
    grids = []
    strike = None if spec.strike is None else spec.strike.phase
    for index, (name, fixed) in enumerate(zip(spec.names, spec.durations, strict=True)):
        guess_phase = spec.guess.phase(name)
        guess = max(guess_phase.duration, 1e-3) if fixed is None else fixed
        step = planner.strike_step if index == strike else planner.step
        if spec.intervals is not None:
            count = spec.intervals[index]
        elif isinstance(planner.intervals, int):
            count = planner.intervals
        elif isinstance(planner.intervals, Mapping) and name in planner.intervals:
            count = planner.intervals[name]
        else:
            count = int(np.clip(5 * np.ceil(guess / step / 5.0), 5, 60))
            if fixed is None:  # room to grow: at least 1.25 x the guess at max_interval
                count = max(count, int(5 * np.ceil(1.25 * guess / planner.max_interval / 5.0)))
        if index == strike and strike_scale > 1:
            count = min(count * strike_scale, MAX_STRIKE_INTERVALS)
        if count > MAX_PHASE_INTERVALS:
            raise InvalidInputError(
                f"phase {name!r} would need {count} intervals (its first guess lasts "
                f"{guess:.3g} s, max_interval is {planner.max_interval:.3g} s), more than "
                f"{MAX_PHASE_INTERVALS}: raise max_interval or set fewer intervals",
                name="max_interval" if spec.intervals is None else "intervals",
            )
        upper = count * planner.max_interval if fixed is None else fixed
        if fixed is None and upper < guess:
            guess = upper
        grids.append(PhaseGrid(name, count, fixed, guess, upper))
    return tuple(grids)


def nlp_options(
    planner: OptimalControl, mu_init: float | None = None
) -> tuple[tuple[str, Any], ...]:
    """The solver options of ``planner`` (its defaults overridden by ``solver_options``), frozen.

    ``mu_init``: IPOPT's first barrier parameter when the first point is closer to the
    solution than IPOPT's own start assumes (:func:`first_barrier`); None for IPOPT's.
    """
    options: dict[str, Any] = {"print_time": False}
    if planner.solver == "ipopt":
        options.update(
            {
                "ipopt.print_level": 0,
                "ipopt.sb": "yes",
                "ipopt.tol": planner.tolerance,
                "ipopt.constr_viol_tol": 1e-9,
                "ipopt.max_iter": planner.max_iterations,
                "ipopt.mu_strategy": "monotone",
                # The rows are already scaled by the limits: MUMPS's own row and column
                # scaling only costs time.
                "ipopt.mumps_permuting_scaling": 0,
                "ipopt.mumps_scaling": 0,
                # IPOPT refines every step at least once by default; these steps meet
                # its residual test without it, so the refinement only costs time.
                "ipopt.min_refinement_steps": 0,
                # IPOPT's heuristics for problems that may be infeasible: while the
                # violation is above 1e-3 (expect_infeasible_problem_ctol) and until the
                # first restoration phase, the line search turns to restoration sooner
                # (no watchdog or soft restoration), and restoration must cut the
                # violation further before it ends. Strikes past the limits then fail
                # sooner; feasible problems are solved by the same iterates.
                "ipopt.expect_infeasible_problem": "yes",
            }
        )
        if mu_init is not None:
            options["ipopt.mu_init"] = mu_init
    elif planner.solver == "sqpmethod":
        options.update(
            {
                "print_header": False,
                "print_iteration": False,
                "print_status": False,
                "max_iter": planner.max_iterations,
                "qpsol_options": {"printLevel": "none"},
            }
        )
    options.update(planner.solver_options)
    return freeze_options(options)


def first_barrier(spec: Spec) -> float | None:
    """IPOPT's first barrier parameter for ``spec``'s cold solves, or None for IPOPT's own.

    :data:`CLOSE_MU_INIT` for a free move whose first nodes sit on its jerk switches,
    :data:`STRIKE_MU_INIT` for a pool strike (warm solves start from the tolerance's, see
    :meth:`planners.ocp.transcription.CompiledNLP.warm`).
    """
    if spec.switch_joint is not None:
        return CLOSE_MU_INIT
    if spec.strike is not None:
        return STRIKE_MU_INIT
    return None


def compiled_nlp(planner: OptimalControl, structure: Structure, robot: Robot) -> CompiledNLP:
    """The compiled NLP of ``structure`` for ``robot``, built once per process.

    From the planner's own cache, else from the process's (:data:`COMPILED`, which every
    planner object shares), else built and kept in both.
    """
    with planner._lock:
        compiled = planner._compiled.get(structure)
        if compiled is not None:
            return compiled
    compiled = COMPILED.get(structure)
    if compiled is None:
        model = MODELS.get_or_build(robot.fingerprint, lambda: SymbolicModel(robot))
        try:
            compiled = COMPILED.get_or_build(structure, lambda: compile_nlp(structure, model))
        except RuntimeError as error:
            if not planner.solver_options:
                raise
            raise InvalidInputError(
                f"solver_options {planner.solver_options!r} were refused by the "
                f"{planner.solver} plugin: {casadi_reason(str(error))}",
                name="solver_options",
            ) from error
    with planner._lock:
        return planner._compiled.setdefault(structure, compiled)


def build_problem(
    planner: OptimalControl,
    problem: Any,
    spec: Spec,
    weights: dict[str, float],
    torque_nodes: tuple[int, ...],
    strike_scale: int | None,
    warm_start: Trajectory | None,
    torque_margin: float | None = None,
    row_margins: FloatArray | None = None,
    position_rows: bool | None = None,
    shrink: FloatArray | None = None,
) -> OptimalControlProblem:
    """The NLP of one round: grids, structure, bounds, parameters and the initial point."""
    grids = planner._grids(spec, strike_scale or 1)
    intervals = tuple(g.intervals for g in grids)
    first = np.concatenate([[0], np.cumsum(intervals)]).astype(int)
    nodes = int(first[-1]) + 1
    linear = planner.torque_rows == "linear"
    if planner.torque is True or (linear and torque_nodes):
        torque_nodes = tuple(range(nodes))
    margin = planner.torque_margin if torque_margin is None else torque_margin
    structure = Structure(
        robot=spec.robot.fingerprint,
        limits=structure_limits(spec.limits),
        tool_frame=spec.robot.tool_frame,
        intervals=intervals,
        free=tuple(g.duration is None for g in grids),
        free_grid=planner.free_grid,
        tasks=spec.tasks,
        position_rows=planner.position_rows is True if position_rows is None else position_rows,
        torque_nodes=tuple(n for n in torque_nodes if n < nodes),
        torque_rows=planner.torque_rows,
        weights=tuple(sorted(weights.items())),
        margin=planner.margin,
        torque_margin=0.0 if linear else margin,  # linear rows: in their coefficients
        solver=planner.solver,
        options=planner._options(first_barrier(spec)),
    )
    compiled = planner._compile(structure, spec.robot)
    keep = 1.0 - planner.margin
    lbx, ubx = _decision_bounds(spec, grids, compiled, first, keep, planner.max_interval, shrink)

    x0, lam_x0, lam_g0 = planner._initial(spec, grids, compiled, lbx, ubx, warm_start)
    params: dict[str, Any] = {"time_scale": sum(g.guess for g in grids)}
    for task in spec.tasks:
        params.update(task.values())
    saved = None if warm_start is None else warm_start.metadata.get("warm_start")
    if lam_g0 is not None and isinstance(saved, WarmStart) and saved.time_scale:
        params["time_scale"] = saved.time_scale  # the multipliers' objective
    if linear:  # expanded about the initial point: the previous solution or the guess
        room = fixed_room(
            spec, first, structure.torque_nodes, margin if row_margins is None else row_margins
        )
        params["torque"] = torque_linearization(compiled, x0, room)
    if "anchor" in compiled.parameters.names:
        params["anchor"] = x0[: compiled.layout.K]
    p = compiled.parameters.vector(**params)
    return OptimalControlProblem(
        problem=problem,
        compiled=compiled,
        grids=grids,
        x0=x0,
        lbx=lbx,
        ubx=ubx,
        p=p,
        lam_x0=lam_x0,
        lam_g0=lam_g0,
        contact=spec.contact,
        guess=spec.guess,
    )


def _decision_bounds(
    spec: Spec,
    grids: tuple[PhaseGrid, ...],
    compiled: CompiledNLP,
    first: NDArray[np.int_],
    keep: float,
    max_interval: float,
    shrink: FloatArray | None,
) -> tuple[FloatArray, FloatArray]:
    """Scaled bounds (lbx, ubx) of the decision vector: grid, limits, strike caps, fixed states.

    ``first`` holds each phase's first node, ``keep`` the fraction of the limits kept and
    ``shrink`` the node position bounds moved in, shape (nodes, 2, n) [rad or m], or None.
    """
    layout = compiled.layout
    half = compiled.scale[1]
    lbx = np.empty(layout.size)
    ubx = np.empty(layout.size)
    for i, grid in enumerate(grids):
        index = slice(layout.first_node[i], layout.first_node[i + 1])
        if grid.duration is None:
            lbx[index], ubx[index] = MIN_INTERVAL, max_interval
        else:
            lbx[index] = ubx[index] = grid.duration / grid.intervals
    x_lower = np.concatenate([-np.ones(spec.limits.n), -keep * np.ones(2 * spec.limits.n)])
    lbx[layout.x_start : layout.u_start] = np.tile(x_lower, layout.nodes)
    ubx[layout.x_start : layout.u_start] = np.tile(-x_lower, layout.nodes)
    lbx[layout.u_start :] = -keep
    ubx[layout.u_start :] = keep
    if spec.strike is not None and spec.contact is not None:
        _cap_strike_nodes(lbx, ubx, spec.contact.ratio, spec.strike.nodes(first), layout, keep)
    if shrink is not None:  # node position bounds moved in (fixed states override them)
        for node in range(layout.nodes):
            index = layout.x_index(node, 0)
            lbx[index] = -1.0 + shrink[node, 0] / half
            ubx[index] = 1.0 - shrink[node, 1] / half
    for fixed in spec.fixed:  # last: they override the bounds above
        fixed.pin(lbx, ubx, layout, compiled.scale, first)
    return lbx, ubx


def _cap_strike_nodes(
    lbx: FloatArray,
    ubx: FloatArray,
    ratio: float,
    nodes: range,
    layout: Layout,
    keep: float,
) -> None:
    """Bound the strike ``nodes``' velocities and accelerations by :func:`strike_caps`, in place.

    ``ratio`` is the contact's largest fraction of a velocity limit [-].
    """
    caps = strike_caps(ratio, keep)
    for node in nodes:
        for block, cap in ((1, caps[0]), (2, caps[1])):
            index = layout.x_index(node, block)
            lbx[index], ubx[index] = -cap, cap


def initial_point(
    planner: OptimalControl,
    spec: Spec,
    grids: tuple[PhaseGrid, ...],
    compiled: CompiledNLP,
    lbx: FloatArray,
    ubx: FloatArray,
    warm_start: Trajectory | None,
) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
    """Initial primal (and dual) values: a previous solution, or a guess at the nodes.

    A guess is sampled at the nodes and fitted to the dynamics rows (:func:`integrable`).
    """
    if warm_start is not None:
        saved = warm_start.metadata.get("warm_start")
        if isinstance(saved, WarmStart):
            lam_g = constraint_duals(saved, compiled)
            if (
                lam_g is not None
                and compiled.structure.torque_nodes
                and not (saved.structure.torque_nodes)
            ):
                # The first torque rows, which the last solution breaks: a solve from
                # its primal values with a fresh barrier takes fewer iterations than one
                # from its multipliers at the warm start's small barrier.
                return np.clip(saved.w, lbx, ubx), None, None
            if lam_g is not None:
                return np.clip(saved.w, lbx, ubx), saved.lam_x, lam_g
    source = spec.guess
    if warm_start is not None:
        wanted = [g.name for g in grids]
        have = [p.name for p in warm_start.phases]
        if not set(wanted) <= set(have):
            raise InvalidInputError(
                f"warm_start has the phases {have}, this problem needs {wanted}: a warm "
                "start must have every phase of the problem (by name)",
                name="warm_start",
            )
        source = warm_start
    layout = compiled.layout
    x0 = _sampled(source, grids, compiled, _switch_grid(planner, spec, grids, source))
    kept = {int(node) for node in layout.first_node}
    if spec.strike is not None:
        kept.update(spec.strike.nodes(layout.first_node))
    return np.clip(integrable(x0, layout, compiled.scale, sorted(kept)), lbx, ubx), None, None


def _sampled(
    source: Trajectory,
    grids: tuple[PhaseGrid, ...],
    compiled: CompiledNLP,
    switches: FloatArray | None,
) -> FloatArray:
    """A point of ``source``'s states at the nodes (scaled), its grid even in each phase.

    ``switches``: the node times [s] of a one-phase grid instead (:func:`_switch_grid`).
    """
    layout = compiled.layout
    mid, half, vel, acc, _ = compiled.scale
    x0 = np.zeros(layout.size)
    for i, grid in enumerate(grids):
        window = source.phase(grid.name)
        duration = window.duration if grid.duration is None else grid.duration
        x0[layout.first_node[i] : layout.first_node[i + 1]] = duration / grid.intervals
        times = np.linspace(window.t_start, window.t_end, grid.intervals + 1)
        if switches is not None:
            x0[: layout.K] = np.diff(switches)
            times = switches
        sample = source.sample(times)
        first = int(layout.first_node[i])
        for j in range(grid.intervals + 1):
            node = first + j
            x0[layout.x_index(node, 0)] = (sample.q[j] - mid) / half
            x0[layout.x_index(node, 1)] = sample.qd[j] / vel
            x0[layout.x_index(node, 2)] = sample.qdd[j] / acc
    return x0


def _switch_grid(
    planner: OptimalControl, spec: Spec, grids: tuple[PhaseGrid, ...], source: Trajectory
) -> FloatArray | None:
    """The first nodes' times [s] of a free one-phase move guessed by Ruckig, else None.

    On the jerk switches of :attr:`Spec.switch_joint` (:func:`switch_times`); None for
    any other first point (a warm start, several phases, a fixed duration).
    """
    if (
        spec.switch_joint is None
        or source is not spec.guess
        or len(grids) != 1
        or grids[0].duration is not None
    ):
        return None
    times = switch_times(spec.guess, spec.switch_joint, grids[0].intervals, planner.max_interval)
    if times is None or times[-1] > grids[0].upper:
        return None
    return times
