r"""Strikes and joint moves as constrained optimal control problems, solved with CasADi.

:class:`OptimalControl` poses a problem as a multi-phase nonlinear program
(:mod:`planners.ocp.transcription`: piecewise-constant jerk, exact triple-integrator steps,
limits that hold between the nodes) and solves it with IPOPT (or another CasADi NLP solver
chosen by name).

Problems and their phases
    * :class:`problems.PointToPoint`: one phase ``move`` (free duration unless the problem
      fixes it), any start and goal state.
    * :class:`problems.Waypoints`: one phase per segment, through every waypoint (within
      ``via_tolerance`` when set), rest at both ends.
    * :class:`problems.PoolStrike`: ``approach`` (free), ``strike`` (the window: the cue tip on
      the constant-speed schedule through the contact point, cue axis on the line, roll
      free), ``stop`` (free, rest anywhere).
    * :class:`problems.PaddleStrike`: ``approach`` lasting the contact time and ending at the
      contact configuration with the ball point moving at the strike speed along the paddle
      normal, then ``stop``; with speed 0 (the ECE486 paddle task) the approach ends at rest.

The contact configuration, objectives, torque limits, verification, build and solve apart,
warm starts, failures and solve statistics are described in :mod:`planners.ocp`.

Example::

    problem = problems.sawyer_pool_shot(1.0)
    traj = OptimalControl("time").plan(problem)
    planners.check(traj, problem).ok
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InvalidInputError,
    SolverError,
)
from optraj.planners.base import CompiledCache, stamp
from optraj.planners.ocp.building import (
    build_problem,
    compiled_nlp,
    initial_point,
    nlp_options,
    phase_grids,
)
from optraj.planners.ocp.clearance import Clearance, checked_clearance
from optraj.planners.ocp.failures import (
    solver_cause,
)
from optraj.planners.ocp.formulation import (
    check_strike_start_held,
    checked_warm_start,
    held_spec,
    keep_switch_grid,
    problem_spec,
)
from optraj.planners.ocp.options import (
    BUDGET_SPENT,
    FIT_JERK_WEIGHT,
    GRID_WEIGHT,
    INFEASIBLE_STATUSES,
    KEPT_NODE_WEIGHT,
    LINE_SAMPLES,
    LINE_SAMPLES_FINE,
    MAX_PHASE_INTERVALS,
    MAX_SHRINK,
    MAX_STRIKE_INTERVALS,
    MIN_INTERVAL,
    OBJECTIVES,
    PHASE_NAMES,
    POSITION_SHRINKS,
    ROUNDS,
    SHRINK_EXTRA,
    SOLVERS,
    STRIKE_ACCELERATION_ROOM,
    STRIKE_GRID_WEIGHT,
    STRIKE_VELOCITY_ROOM,
    TIGHT_RATIO,
    TIME_BUDGET,
    TORQUE_POINTS,
    TORQUE_WATCH,
    checked_fraction,
    checked_intervals,
    checked_max_interval,
    checked_position_rows,
    checked_solver_options,
    checked_torque,
    objective_weights,
    solver_name,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
    PhaseGrid,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.refinement import (
    strike_caps,
)
from optraj.planners.ocp.rounds import (
    round_weights,
    solve_rounds,
    strike_misses,
    torque_nodes,
    torque_ratios,
)
from optraj.planners.ocp.solution import (
    with_totals,
)
from optraj.planners.ocp.solve import call_solver, check_budget, solve_built
from optraj.planners.ocp.strike_search import (
    alone_error,
    attempt,
    plan_pool_strike,
    strike_error,
    window_ratio,
)
from optraj.planners.ocp.transcription import (
    TORQUE_ROWS,
    CompiledNLP,
    Structure,
    deadline,
)
from optraj.planners.strike.contact import (
    MAX_CANDIDATES,
)
from optraj.planners.strike.window_check import WindowCheck
from optraj.planners.trajectory import Trajectory
from optraj.problems import PoolStrike
from optraj.validation import (
    MAX_DURATION,
    as_choice,
    as_count,
    as_duration,
    as_flag,
    as_number,
    as_positive,
)

__all__ = [
    "BUDGET_SPENT",
    "FIT_JERK_WEIGHT",
    "GRID_WEIGHT",
    "INFEASIBLE_STATUSES",
    "KEPT_NODE_WEIGHT",
    "LINE_SAMPLES",
    "LINE_SAMPLES_FINE",
    "MAX_PHASE_INTERVALS",
    "MAX_SHRINK",
    "MAX_STRIKE_INTERVALS",
    "MIN_INTERVAL",
    "OBJECTIVES",
    "PHASE_NAMES",
    "POSITION_SHRINKS",
    "ROUNDS",
    "SHRINK_EXTRA",
    "SOLVERS",
    "STRIKE_ACCELERATION_ROOM",
    "STRIKE_GRID_WEIGHT",
    "STRIKE_VELOCITY_ROOM",
    "TIGHT_RATIO",
    "TIME_BUDGET",
    "TORQUE_POINTS",
    "TORQUE_WATCH",
    "OptimalControl",
    "OptimalControlProblem",
    "PhaseGrid",
    "WarmStart",
    "strike_caps",
]

FloatArray = NDArray[np.float64]

#: The clearance a pool strike keeps by default (:class:`planners.ocp.clearance.Clearance`).
DEFAULT_CLEARANCE = Clearance()


class OptimalControl(CompiledCache):
    """Plan by constrained optimal control: multi-phase, jerk-limited, torque-aware.

    Args:
        objective: ``"time"``, ``"jerk"``, ``"effort"``, or a mapping of weights.
        solver: CasADi NLP plugin (:data:`SOLVERS`); IPOPT by default.
        solver_options: Options passed to ``casadi.nlpsol`` (they override the defaults).
        intervals: Intervals per phase: an int for every phase or a mapping from phase name
            (:data:`PHASE_NAMES`, or ``"segment <k>"`` of a :class:`problems.Waypoints`);
            chosen from ``step`` for the phases it does not name, or all when None.
        step: Target interval length of the approach and stop phases [s]; the interval
            count it gives a phase is kept within 5 to 60 (set ``intervals`` for others).
        strike_step: Target interval length of a strike window [s].
        max_interval: Longest interval a free phase may stretch to [s].
        margin: Fraction of the velocity, acceleration and jerk limits kept free [-].
        torque: ``"auto"``, True or False (see the module docstring).
        position_rows: ``"auto"`` or True: when the rows that bound positions between nodes
            come in (see the module docstring).
        torque_margin: Fraction of the torque limits kept free at torque rows [-]; rounds
            go on while a torque passes ``1 - torque_margin / 2`` of its limit. The default
            (0.03) leaves room for the linear rows' expansion error and for peaks between
            nodes.
        torque_rows: ``"linear"`` or ``"rnea"`` (see the module docstring).
        regularization: Weight of the small jerk (and posture) terms [-].
        stretch: Factor on the minimum durations when the objective has no time term [-].
        max_iterations: Iteration cap of the solver.
        tolerance: Solver tolerance (IPOPT ``tol``: the scaled optimality error at which it
            stops; the constraints are met to 1e-9 whatever it is) [-].
        contact_candidates: Contact configurations compared for a strike.
        contact_retries: Other contact configurations (other IK branches, next best first)
            a pool strike is solved from when the solver fails from the chosen one, >= 0.
            When every one fails, the contact search runs once more over twice as many
            candidates and its new branches (as many again) are tried too; the last
            failure is raised. 0 solves from the chosen configuration only. Once the
            solver has found a strike infeasible, a configuration is solved from only if
            its strike window can keep within the limits
            (:class:`planners.strike.window_check.WindowCheck`, far cheaper than a failing
            solve).
        free_grid: Whether each interval of a free phase has its own length (else all
            intervals of a phase are equal).
        reuse_contact: Whether a pool strike warm started from a previous pool solution
            first keeps that solution's contact branch when it still has room
            (:func:`planners.strike.contact.contact_near`, one local IK instead of the contact
            search). The branch then stays the same from one re-plan to
            the next, but it may not be the one a cold plan picks (the branch the arm
            reaches soonest), so the motion may take longer. When its solve fails, the
            contact search runs as without a warm start.
        time_budget: Wall time one :meth:`plan` (or :meth:`solve`) may take [s], building
            the NLPs included, in [1e-6, 86400]; None for no limit. The solver is stopped at
            its first iteration past it and the plan raises a ``SolverError`` with status
            :data:`BUDGET_SPENT`.
        clearance: How far a pool strike keeps the arm and cue above the cloth (the plane
            through the bottom of the ball) and the cue tip off the ball before the strike
            line (:class:`planners.ocp.clearance.Clearance`: the cue's butt, middle and tip
            1 cm above the cloth, the tip 1 cm off the ball, 3 mm more at the grid nodes, in
            m; a wrist sphere on request), or None for no such rows. Other problems have
            none.
    """

    caches = ("_compiled",)

    _weights = round_weights
    _rounds = solve_rounds
    _torque_ratios = staticmethod(torque_ratios)
    _torque_nodes = torque_nodes
    _strike_misses = strike_misses
    _grids = phase_grids
    _options = nlp_options
    _compile = compiled_nlp
    _build = build_problem
    _initial = initial_point
    _call = call_solver
    _in_budget = check_budget
    _solve = solve_built
    _window = window_ratio
    _alone_error = alone_error
    _strike_error = strike_error
    _attempt = attempt
    _pool_strike = plan_pool_strike
    _spec = problem_spec
    _held = held_spec
    _strike_start_held = check_strike_start_held

    def __init__(
        self,
        objective: str | Mapping[str, float] = "time",
        *,
        solver: str = "ipopt",
        solver_options: Mapping[str, Any] | None = None,
        intervals: int | Mapping[str, int] | None = None,
        step: float = 0.08,
        strike_step: float = 0.03,
        max_interval: float = 0.1,
        margin: float = 1e-4,
        torque: bool | str = "auto",
        torque_margin: float = 0.03,
        position_rows: bool | str = "auto",
        torque_rows: str = "linear",
        regularization: float = 1e-2,
        stretch: float = 1.2,
        max_iterations: int = 1000,
        tolerance: float = 1e-6,
        contact_candidates: int = 16,
        contact_retries: int = 2,
        free_grid: bool = True,
        reuse_contact: bool = True,
        time_budget: float | None = TIME_BUDGET,
        clearance: Clearance | None = DEFAULT_CLEARANCE,
    ) -> None:
        self.weights = objective_weights(objective)
        self.objective = objective if isinstance(objective, str) else dict(self.weights)
        self.solver = solver_name(solver)
        self.solver_options = checked_solver_options(solver_options)
        self.intervals = checked_intervals(intervals)
        self.step = as_positive(step, "step", "s", maximum=MAX_DURATION)
        self.strike_step = as_positive(strike_step, "strike_step", "s", maximum=MAX_DURATION)
        self.max_interval = checked_max_interval(max_interval)
        self.margin = checked_fraction("margin", margin)
        self.torque_margin = checked_fraction("torque_margin", torque_margin)
        self.torque = checked_torque(torque)
        self.position_rows = checked_position_rows(position_rows)
        as_choice(torque_rows, "torque rows", TORQUE_ROWS)
        self.torque_rows = torque_rows
        self.regularization = as_number(regularization, "regularization", minimum=0.0)
        self.stretch = as_number(stretch, "stretch", minimum=1.0)
        self.max_iterations = as_count(max_iterations, "max_iterations", 1)
        self.tolerance = as_positive(tolerance, "tolerance", maximum=1.0)
        self.contact_candidates = as_count(
            contact_candidates, "contact_candidates", 1, MAX_CANDIDATES
        )
        self.contact_retries = as_count(contact_retries, "contact_retries", 0, 100)
        self.free_grid = as_flag(free_grid, "free_grid")
        self.reuse_contact = as_flag(reuse_contact, "reuse_contact")
        self.time_budget = None if time_budget is None else as_duration(time_budget, "time_budget")
        self.clearance = checked_clearance(clearance)
        self._compiled: dict[Structure, CompiledNLP] = {}
        self._lock = threading.Lock()
        self._window_check = WindowCheck()

    def __repr__(self) -> str:
        """Objective and solver."""
        return f"OptimalControl(objective={self.objective!r}, solver={self.solver!r})"

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata."""
        label = self.objective if isinstance(self.objective, str) else "weighted"
        return f"optimal control (min {label})" if label != "weighted" else "optimal control"

    # -- the public face ---------------------------------------------------------------------

    def plan(self, problem: Any, warm_start: Trajectory | None = None) -> Trajectory:
        """Solve the problem; the result's metadata holds the solve statistics.

        Args:
            problem: A PointToPoint, Waypoints, PoolStrike or PaddleStrike.
            warm_start: A previous solution or any trajectory with the problem's phases. A
                previous pool solution also lends its contact branch: when that still has
                room (:func:`planners.strike.contact.contact_near`) the contact search is skipped
                (``metadata["contact_from_warm_start"]``).

        Returns:
            The trajectory, exactly the solver's piecewise cubic.

        Raises:
            InfeasibleError: A strike no contact configuration can make (with the binding
                joint and the best reachable speed): one that needs more than the velocity
                limits at every contact found, or a pool strike the solver found infeasible
                whose strike windows each need more than the limits at every contact tried
                (:class:`planners.strike.window_check.WindowCheck`; the error names the window's
                binding joint and quantity and the speed its motion allows). Also a fixed
                duration shorter than the limits allow, or torque limits that stay exceeded.
            SolverError: The solver failed; its status and the most violated constraint
                group are in the message (for a pool strike, the last contact tried). A pool
                strike found infeasible that needs more than :data:`TIGHT_RATIO` of a
                velocity limit at every contact tried also has that ratio, the binding joint
                and the fastest speed the velocity limits allow in it; with
                ``contact_retries=0``, also the window check's finding when that contact's
                window needs more than the limits.
            InvalidInputError: An unsupported problem.
            SolverError: With status :data:`BUDGET_SPENT`: the plan took its
                ``time_budget``.
        """
        with deadline(self._budget()):
            return self._planned(problem, warm_start)

    def _budget(self) -> float:
        """The time budget [s] as a deadline length (inf: none)."""
        return math.inf if self.time_budget is None else self.time_budget

    def _planned(self, problem: Any, warm_start: Trajectory | None) -> Trajectory:
        """:meth:`plan` within its deadline."""
        started = time.perf_counter()
        warm_start = checked_warm_start(problem, warm_start)
        if isinstance(problem, PoolStrike):
            return self._pool_strike(problem, warm_start, started)
        return self._plan_alone(problem, warm_start, started)

    def _plan_alone(
        self,
        problem: Any,
        warm_start: Trajectory | None,
        started: float,
        searching: float = 0.0,
    ) -> Trajectory:
        """Plan from the problem's own spec (a strike's from its contact choice only).

        ``searching`` is the wall time of contact choices before it [s].
        """
        spec = self._spec(problem)
        try:
            traj = self._plan(problem, spec, warm_start)
        except SolverError as error:
            if (
                not isinstance(problem, PoolStrike)
                or spec.contact is None
                or error.status == BUDGET_SPENT
            ):
                raise
            raised = self._alone_error(error, problem, spec.contact, searched=True)
            raise raised from solver_cause(raised, error)
        return stamp(traj, self.name, started, contact_time=searching + spec.contact_time)

    def _plan(self, problem: Any, spec: Spec, warm_start: Trajectory | None) -> Trajectory:
        """Solve from a spec: with no time term, free durations are first minimised."""
        weights = self._weights(spec)
        if "time" not in self.weights and any(d is None for d in spec.durations):
            timed = self._rounds(problem, spec, self._weights(spec, time_only=True), None)
            spec.durations = tuple(
                self.stretch * phase.duration if d is None else d
                for d, phase in zip(spec.durations, timed.phases, strict=True)
            )
            spec.guess = timed
            spec.switch_joint = None  # fixed durations: an even grid, as for any other
            traj = self._rounds(problem, spec, weights, None)
            return with_totals(traj, [timed, traj])
        return self._rounds(problem, spec, weights, warm_start)

    def build(self, problem: Any, warm_start: Trajectory | None = None) -> OptimalControlProblem:
        """The NLP of a problem with its bounds and initial guess, not yet solved.

        With an objective that has no time term, free durations stay free here (the
        two-step solve of :meth:`plan` fixes them). With ``position_rows="auto"`` the NLP is
        the first round's: positions bounded at the nodes only (:meth:`plan` checks them
        between nodes and solves again with the rows when one passes its limit).
        """
        warm_start = checked_warm_start(problem, warm_start)
        spec = self._spec(problem)
        keep_switch_grid(spec, warm_start)
        return self._build(problem, spec, self._weights(spec), (), None, warm_start)

    def solve(self, built: OptimalControlProblem) -> Trajectory:
        """Solve a built problem.

        Raises:
            SolverError: The solver failed (status, iterations, most violated group).
        """
        if not isinstance(built, OptimalControlProblem):
            raise InvalidInputError(
                f"solve takes the OptimalControlProblem of build(), got {type(built).__name__}",
                name="built",
            )
        started = time.perf_counter()
        with deadline(self._budget()):
            traj = self._solve(built)
        return stamp(traj, self.name, started)
