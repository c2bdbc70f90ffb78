"""One solver call on a built problem: warm started when it can be, redone cold on failure."""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    SolverError,
)
from optraj.planners.ocp.options import (
    BUDGET_SPENT,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
    WarmStart,
)
from optraj.planners.ocp.solution import (
    SolverCall,
    casadi_reason,
    diagnosis,
    evaluation_time,
    solution_trajectory,
)
from optraj.planners.ocp.transcription import (
    time_left,
)
from optraj.planners.trajectory import Trajectory

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]


def call_solver(
    planner: OptimalControl, built: OptimalControlProblem, solver: ca.Function, args: dict[str, Any]
) -> SolverCall:
    """One solver call.

    Its ``error`` is set when the solver raised, did not succeed, or left a constraint
    group violated by more than 1e-6 (scaled).

    Raises:
        SolverError: Status :data:`BUDGET_SPENT`: the plan's deadline passed before or
            during the call.
    """
    planner._in_budget(None, "a solve")
    with built.compiled.lock:
        started = time.perf_counter()
        try:
            result = solver(**args)
        except RuntimeError as error:  # the plugin raised instead of returning a status
            stats = solver.stats()
            raised = SolverError(
                planner.solver,
                str(stats.get("return_status", "exception")),
                iterations=int(stats.get("iter_count", -1)),
                detail=casadi_reason(str(error)),
            )
            raised.__cause__ = error
            wall = time.perf_counter() - started
            return SolverCall(np.zeros(0), {}, stats, wall, math.inf, raised)
        wall = time.perf_counter() - started
        stats = solver.stats()
    w = np.asarray(result["x"]).reshape(-1)
    violations = built._violations(w)
    worst = max(violations.values())
    failure: SolverError | None = None
    if not stats.get("success", False) or not np.all(np.isfinite(w)) or worst > 1e-6:
        failure = SolverError(
            planner.solver,
            str(stats.get("return_status", "unknown")),
            iterations=int(stats.get("iter_count", -1)),
            detail=diagnosis(built, w) if np.all(np.isfinite(w)) else "no finite point",
        )
        planner._in_budget(failure, "a solve")
    return SolverCall(w, result, stats, wall, worst, failure)


def check_budget(planner: OptimalControl, failure: SolverError | None, what: str) -> None:
    """Raise the budget's ``SolverError`` when this plan's deadline has passed.

    Args:
        planner: The planner whose budget it is.
        failure: The last solver failure, whose finding the error repeats, or None.
        what: What the deadline stopped, e.g. ``"a solve"``.
    """
    if time_left() > 0.0:
        return
    found = f"; the last solve failed: {failure}" if failure is not None else ""
    raise SolverError(
        planner.solver,
        BUDGET_SPENT,
        iterations=None if failure is None else failure.iterations,
        detail=f"the plan took its time_budget of {planner._budget():.4g} s, which stopped "
        f"{what}{found}; a larger time_budget, looser limits or an easier problem may plan",
    )


def solve_built(planner: OptimalControl, built: OptimalControlProblem) -> Trajectory:
    """Solve ``built``: warm from its multipliers when it has them, cold again when that fails."""
    compiled = built.compiled
    args: dict[str, Any] = {
        "x0": built.x0,
        "lbx": built.lbx,
        "ubx": built.ubx,
        "lbg": compiled.lbg,
        "ubg": compiled.ubg,
        "p": built.p,
    }
    abandoned: SolverCall | None = None
    if built.lam_x0 is not None:
        warm = {**args, "lam_x0": built.lam_x0, "lam_g0": built.lam_g0}
        call = planner._call(built, compiled.warm(), warm)
        if call.error is not None:
            # The multipliers led nowhere within WARM_ITERATIONS (a previous solution
            # whose active set is far from this problem's): solve again from the same
            # primal point with the cold solver's fresh barrier.
            abandoned, call = call, planner._call(built, compiled.solver, args)
    else:
        call = planner._call(built, compiled.solver, args)
    if call.error is not None:
        raise call.error
    w, stats = call.w, call.stats
    dropped = (0, 0.0, 0.0) if abandoned is None else abandoned.spent()
    traj = solution_trajectory(built, w)
    traj.metadata.update(
        {
            "solver": planner.solver,
            "status": "ok",
            "solver_status": str(stats.get("return_status", "unknown")),
            "iterations": int(stats.get("iter_count", -1)) + dropped[0],
            "nlp_time": call.wall + dropped[1],
            "evaluation_time": evaluation_time(stats) + dropped[2],
            "objective": float(call.result["f"]),
            "constraint_violation": call.worst,
            "warm_started": built.lam_x0 is not None,
            "warm_abandoned": abandoned is not None,
            "intervals": {g.name: g.intervals for g in built.grids},
            "variables": built.variables,
            "constraints": built.constraints,
            "warm_start": WarmStart(
                compiled.structure,
                w,
                np.asarray(call.result["lam_x"]).reshape(-1),
                np.asarray(call.result["lam_g"]).reshape(-1),
                float(built.parameter("time_scale")[0]),
            ),
        }
    )
    if built.contact is not None:
        traj.metadata["contact_speed_ratio"] = built.contact.ratio
        traj.metadata["contact_max_speed"] = built.contact.max_speed
        traj.metadata["contact_configuration"] = np.array(built.contact.q, dtype=float)
    return traj
