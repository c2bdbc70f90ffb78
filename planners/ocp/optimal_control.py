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
      normal, then ``stop``; with speed 0 (the seed's task) the approach ends at rest.

Contact configuration
    A strike's contact configuration is chosen before the NLP is built
    (:func:`planners.strike.contact.choose_contact`): the IK solution whose Jacobian lets the tool
    reach the strike speed with the smallest joint speeds. A strike no configuration can make
    is rejected there, within a second, with the binding joint and the best reachable speed.
    That check covers the velocity limits only. Close to the fastest speed it allows, the
    line can also need accelerations past their limits, and IPOPT finds the NLP locally
    infeasible. Each further contact is then solved from only if its strike window, with
    the approach into it and the stop after it, can keep within the limits
    (:class:`planners.strike.window_check.WindowCheck`). When no window tried can, the plan raises
    an ``InfeasibleError`` naming the window's binding joint and quantity and a slower speed
    (with ``contact_retries=0``, a ``SolverError`` that says so: other contacts may plan);
    otherwise the last ``SolverError``, whose message adds (when every contact tried needs
    more than :data:`TIGHT_RATIO` of a velocity limit) the ratio, the binding joint and the
    fastest speed the velocity limits allow. Of the first 40 strike benchmark balls at 1.2,
    1.35, 1.45 and 1.5 m/s on Sawyer (160 strikes, a planner per speed), 78 plan; 51 are
    refused by the contact choice and the other 31 after a window check, in 0.3 to 2.3 s (29
    within 1 s; the slowest is a first solve of 300 iterations).
    The chosen contact's ratio (the largest fraction of a velocity limit the line needs)
    also bounds the joint velocities and accelerations at the strike nodes
    (:func:`strike_caps`); the bounds come inside the limits when the ratio is below about
    a third, in slow strikes. Without them a minimum-time plan spends a slow strike's long
    window on self-motion of the redundant arm: it ends the approach with the joints still
    moving fast and brakes them inside the window, and that motion carries the cue off its
    line between nodes.

Objectives
    ``"time"`` (sum of the free phase durations), ``"jerk"`` (integral of the squared
    jerk, scaled by the jerk limits), ``"effort"`` (integral of the squared torques, scaled
    by the effort limits), or a mapping of weights, e.g. ``{"time": 1, "jerk": 0.1}``. A
    small ``regularization`` adds the jerk term and, for redundant arms (7 joints or more),
    a posture term that keeps joints near the middle of their ranges (away from the limits;
    singular configurations are avoided by the contact choice). Without a time term free
    durations would grow without bound, so they are first minimised and then fixed at
    ``stretch`` times the minimum.

Torque limits
    A state the problem fixes (the start at rest, a move's goal state) has the torques of
    its inverse dynamics whatever the motion: one that needs more than an effort limit (a
    start holding the arm against gravity with limits scaled down) is refused before any
    contact search or solve
    (:func:`planners.time_optimal.lower_bound.check_state_torques`), with the
    joint and the factor on the effort limits a plan needs at least. Within the limits but
    past the torque margin, its node's rows keep only the room the state leaves, and rounds
    count its own share of the limit as settled.

    By default (``torque="auto"``) the NLP is first solved without torque rows and the
    torques are evaluated densely (4 points per interval); only when one exceeds 90 % of its
    limit do rows come in and the NLP is solved again, warm started. ``torque=True`` has
    rows from the first solve, ``False`` none (the checker still reports the torques).

    ``torque_rows="linear"`` (the default) writes them as the RNEA's first-order expansion
    about the previous solution (about the initial guess in a first solve), at every node:
    linear rows whose coefficients are NLP parameters, so one compiled NLP serves every
    round and every problem of the same grid, and the Hessian stays as without torques.
    Each further round expands about the last solution, primal and dual values carried
    over, until the dense torques hold; at that fixed point the rows agree with the RNEA to
    first order. ``"rnea"`` writes the symbolic RNEA itself, at the nodes around the hot
    intervals only: exact rows, but each new set of nodes is a new NLP to build (about a
    second) and its second derivatives make every iteration several times dearer.
    From the second expansion on, the rows at both ends of an interval whose dense torque
    still breaks its limit keep that excess more room (so rounds settle where the binding
    nodes would otherwise swap back and forth, and torques that peak between nodes hold);
    with RNEA rows the margin of every row widens when rows everywhere are not enough.

Verification
    Limits on velocity, acceleration and jerk hold between nodes by construction. Positions
    are bounded at the nodes, and by default (``position_rows="auto"``) checked exactly
    between them after a solve (the extremes of each interval's cubic). Where a piece passes
    a limit, the bounds of its two nodes on that side move in by the excess and the same NLP
    is solved again, warm (up to :data:`POSITION_SHRINKS` times); only if that does not
    settle is it solved with the rows that bound positions between nodes too (the Bernstein
    rows of :mod:`planners.ocp.transcription`, a third of all rows, which cost about a third of
    a solve's time when they are always there, and a new NLP to build).
    ``position_rows=True`` has the rows from the first solve.
    The strike line is verified between nodes (quarter points of each interval); where the
    cue tip leaves its tolerance the strike phase gets twice the intervals and the NLP is
    solved again. Judge the result with :func:`planners.check`, as for every planner.

Build and solve apart
    :meth:`OptimalControl.build` returns an :class:`OptimalControlProblem` (the CasADi NLP,
    bounds, parameters and initial guess, open for inspection); :meth:`OptimalControl.solve`
    solves it. Compiled NLPs are cached per planner instance and structure (robot, limits,
    intervals, objective), so problems of the same shape reuse one solver; the cache is
    dropped when the planner is pickled.

Warm starts
    ``plan(problem, warm_start=traj)``: from a previous solution of the same shape, primal
    and dual values (``traj.metadata["warm_start"]``); from any other trajectory with the
    same phase names (TOPPRA, Ruckig, classic profiles), its states at the nodes. A previous
    pool solution's contact configuration (``traj.metadata["contact_configuration"]``) is
    tried first for the new strike, one local IK away, before any contact search; when the
    search chooses a contact on another IK branch (more than
    :data:`planners.strike.contact.BRANCH_SPREAD` away on some joint), the plan starts cold. A
    warm solve that has not converged after :data:`planners.ocp.transcription.WARM_ITERATIONS`
    iterations is solved again from the same primal point with a fresh barrier.

Failures and the time budget
    A failed solve's ``SolverError`` names its most violated row by group, joint and place
    (e.g. "dynamics (the acceleration step) of right_j3 at interval 12 of the strike phase")
    and the joint limits the solver's last point presses (:data:`BINDING` of their bounds or
    more, torques by the inverse dynamics at the nodes): at an infeasible NLP's point those
    are what keeps the rows from being met. The window check counts the effort limits too,
    so a strike whose window needs more torque than they give is refused with the joint and
    the limit scale it needs at that speed. Each ``plan`` and ``solve`` runs within
    ``time_budget`` seconds of wall time (:data:`TIME_BUDGET` by default): the solver's
    iteration callback stops it at the deadline
    (:func:`planners.ocp.transcription.stop_callback`), and the plan raises a ``SolverError``
    with status :data:`BUDGET_SPENT` that no contact retry catches.

Solve statistics
    ``plan`` sums over every solve it made: ``metadata["iterations"]`` and
    ``metadata["nlp_time"]`` [s] over all rounds (``round_iterations`` lists them, and
    ``rounds`` counts them), and ``evaluation_time`` [s], the part of ``nlp_time`` spent
    evaluating the NLP's functions and derivatives (the rest is the solver's own work);
    ``contact_time`` [s] is the wall time of the contact choice (0 for a move);
    ``warm_started`` tells whether the first solve started from a previous solution's
    multipliers, and ``warm_abandoned`` whether the last one was dropped for a cold one
    (whose iterations and times are counted too); ``status``, ``objective`` and
    ``constraint_violation`` are the last solve's.

Example::

    problem = problems.sawyer_pool_shot(1.0)
    traj = OptimalControl("time").plan(problem)
    planners.check(traj, problem).ok
"""

from __future__ import annotations

import math
import re
import threading
import time
from collections.abc import Mapping
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    WINDOW_CHECK,
    InfeasibleError,
    InvalidInputError,
    OptrajError,
    SolverError,
)
from optraj.planners.base import CompiledCache, stamp
from optraj.planners.ocp.failures import (
    detailed_failure,
    near_the_limit,
    past_the_limits,
    solver_cause,
)
from optraj.planners.ocp.formulation import (
    checked_warm_start,
    contact_from,
    lends_to,
    paddle_spec,
    point_to_point_spec,
    pool_spec,
    waypoints_spec,
)
from optraj.planners.ocp.guesses import (
    zero_vector,
)
from optraj.planners.ocp.options import (
    BUDGET_SPENT,
    GRID_WEIGHT,
    INFEASIBLE_STATUSES,
    MAX_PHASE_INTERVALS,
    MAX_STRIKE_INTERVALS,
    MIN_INTERVAL,
    OBJECTIVES,
    PHASE_NAMES,
    POSITION_SHRINKS,
    ROUNDS,
    SOLVERS,
    STRIKE_GRID_WEIGHT,
    TIME_BUDGET,
    TORQUE_POINTS,
    TORQUE_WATCH,
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
    constraint_duals,
    fixed_name,
    fixed_ratios,
    fixed_room,
    position_excess,
    shrunk,
    strike_caps,
    tightened,
)
from optraj.planners.ocp.solution import (
    SolverCall,
    casadi_reason,
    dense_times,
    diagnosis,
    evaluation_time,
    integrable,
    solution_trajectory,
    with_totals,
)
from optraj.planners.ocp.transcription import (
    TORQUE_ROWS,
    CompiledNLP,
    Structure,
    compile_nlp,
    deadline,
    freeze_options,
    parameter_vector,
    structure_limits,
    time_left,
    torque_linearization,
)
from optraj.planners.strike.contact import (
    MAX_CANDIDATES,
    ContactChoice,
    choose_contact,
    contact_choices,
)
from optraj.planners.strike.window_check import WindowCheck, WindowRatio
from optraj.planners.time_optimal.lower_bound import check_state_torques
from optraj.planners.trajectory import Trajectory
from optraj.problems import PaddleStrike, PointToPoint, PoolStrike, Waypoints
from optraj.robots import Robot, SymbolicModel
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
    "OBJECTIVES",
    "PHASE_NAMES",
    "SOLVERS",
    "TIME_BUDGET",
    "OptimalControl",
    "OptimalControlProblem",
    "PhaseGrid",
    "WarmStart",
    "strike_caps",
]

FloatArray = NDArray[np.float64]


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
            nodes: on the strike benchmark's binding-torque shots it plans in about 0.8 of
            the rounds' time of 0.01, for motions about 0.3 % longer.
        torque_rows: ``"linear"`` or ``"rnea"`` (see the module docstring).
        regularization: Weight of the small jerk (and posture) terms [-].
        stretch: Factor on the minimum durations when the objective has no time term [-].
        max_iterations: Iteration cap of the solver.
        tolerance: Solver tolerance (IPOPT ``tol``: the scaled optimality error at which it
            stops; the constraints are met to 1e-9 whatever it is) [-]. 1e-5 saves minimum-time
            strikes a few iterations (the strike benchmark's first 40 shots, ball moved 2 cm:
            cold 1322 against 1412, warm re-plans 470 against 539, motions 0.01 % longer) but
            stops a minimum-jerk move of fixed duration 30 % above its optimum.
        contact_candidates: Contact configurations compared for a strike.
        contact_retries: Other contact configurations (other IK branches, next best first)
            a pool strike is solved from when the solver fails from the chosen one, >= 0.
            When every one fails, the contact search runs once more over twice as many
            candidates and its new branches (as many again) are tried too; the last
            failure is raised. 0 solves from the chosen configuration only. Once the
            solver has found a strike infeasible, a configuration is solved from only if
            its strike window can keep within the limits
            (:class:`planners.strike.window_check.WindowCheck`, 30 to 40 ms where a failing solve
            takes 0.3 to 2 s).
        free_grid: Whether each interval of a free phase has its own length (else all
            intervals of a phase are equal).
        reuse_contact: Whether a pool strike warm started from a previous pool solution
            first keeps that solution's contact branch when it still has room
            (:func:`planners.strike.contact.contact_near`, one local IK instead of the contact
            search, about 30 ms less). The branch then stays the same from one re-plan to
            the next, but it may not be the one a cold plan picks (the branch the arm
            reaches soonest), so the motion may take longer. When its solve fails, the
            contact search runs as without a warm start.
        time_budget: Wall time one :meth:`plan` (or :meth:`solve`) may take [s], building
            the NLPs included, in [1e-6, 86400]; None for no limit. The solver is stopped at
            its first iteration past it and the plan raises a ``SolverError`` with status
            :data:`BUDGET_SPENT`.
    """

    caches = ("_compiled", "_models")

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
    ) -> None:
        self.weights = objective_weights(objective)
        self.objective = objective if isinstance(objective, str) else dict(self.weights)
        self.solver = solver_name(solver)
        if solver_options is not None and not isinstance(solver_options, Mapping):
            raise InvalidInputError(
                f"solver_options must be a mapping of option names to values, got "
                f"{solver_options!r}",
                name="solver_options",
            )
        self.solver_options = dict(solver_options or {})
        if intervals is not None and not isinstance(intervals, Mapping):
            intervals = as_count(intervals, "intervals", 1, MAX_PHASE_INTERVALS)
        elif isinstance(intervals, Mapping):
            for key in intervals:
                if not (key in PHASE_NAMES or re.fullmatch(r"segment [1-9][0-9]*", str(key))):
                    raise InvalidInputError(
                        f"intervals names a phase {key!r} that no problem has; phases are "
                        f"{', '.join(PHASE_NAMES)} and 'segment <k>' (Waypoints, from 1)",
                        name="intervals",
                    )
            intervals = {
                str(k): as_count(v, f"intervals[{k!r}]", 1, MAX_PHASE_INTERVALS)
                for k, v in intervals.items()
            }
        self.intervals = intervals
        self.step = as_positive(step, "step", "s", maximum=MAX_DURATION)
        self.strike_step = as_positive(strike_step, "strike_step", "s", maximum=MAX_DURATION)
        self.max_interval = as_positive(max_interval, "max_interval", "s", maximum=MAX_DURATION)
        if self.max_interval <= MIN_INTERVAL:
            raise InvalidInputError(
                f"max_interval must be > {MIN_INTERVAL:g} s (the shortest interval), got "
                f"{self.max_interval:.6g} s",
                name="max_interval",
            )
        for name, value in (("margin", margin), ("torque_margin", torque_margin)):
            fraction = as_number(value, name, minimum=0.0, maximum=0.5)
            if fraction == 0.5:
                raise InvalidInputError(f"{name} must be < 0.5, got {value!r}", name=name)
            setattr(self, name, fraction)
        if not (isinstance(torque, bool) or (isinstance(torque, str) and torque == "auto")):
            raise InvalidInputError(
                f"torque must be 'auto', True or False, got {torque!r}", name="torque"
            )
        self.torque = torque
        if not (
            position_rows is True or (isinstance(position_rows, str) and position_rows == "auto")
        ):
            raise InvalidInputError(
                f"position_rows must be 'auto' or True, got {position_rows!r}",
                name="position_rows",
            )
        self.position_rows = position_rows
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
        self._compiled: dict[Structure, CompiledNLP] = {}
        self._models: dict[str, SymbolicModel] = {}
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
        if isinstance(problem, PoolStrike):  # before any contact search (_spec checks others)
            self._strike_start_held(problem)
        tried: list[FloatArray] = []
        failure: SolverError | None = None
        # Re-planning from a previous pool solution: first its contact branch, if it still
        # has room (one local IK instead of the search).
        seeded = None
        searching = 0.0  # the contact choices' wall time [s]
        if self.reuse_contact and isinstance(problem, PoolStrike):
            seeded = contact_from(problem, warm_start, self.margin)
            searching = time.perf_counter() - started
        found: list[ContactChoice] = []  # the searches' choices tried (for the hint)
        windows: list[WindowRatio | None] = []  # their windows, once a solve was infeasible
        if seeded is not None:
            tried.append(seeded.q)
            outcome = self._attempt(
                problem, seeded, warm_start, len(tried), started, searching, True
            )
            if isinstance(outcome, Trajectory):
                return outcome
            if self.contact_retries == 0:  # the one configuration allowed
                raised = self._alone_error(outcome, problem, seeded, searched=False)
                raise raised from solver_cause(raised, outcome)
            failure, warm_start = outcome, None
        if not isinstance(problem, PoolStrike) or self.contact_retries == 0:
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
        # The contact search once as set, then once more over twice as many candidates for
        # branches it missed; a warm start fits the first branch only.
        for candidates in (self.contact_candidates, 2 * self.contact_candidates):
            self._in_budget(failure, "the contact search")
            searched = time.perf_counter()
            try:
                choices = contact_choices(
                    problem,
                    1 + self.contact_retries,
                    candidates=candidates,
                    exclude=tried,
                    margin=self.margin,
                )
            except InfeasibleError:
                if failure is None:
                    raise
                break  # the wider search refused what the first accepted: report the solver
            finally:
                searching += time.perf_counter() - searched
            for choice in choices:
                tried.append(choice.q)
                found.append(choice)
                # After an infeasible solve, a choice is solved from only if its window can
                # keep within the limits.
                window = self._window(problem, choice, failure)
                windows.append(window)
                if past_the_limits(window):
                    continue
                # None after a seeded try, or for a choice on another branch than its own.
                lend = len(tried) == 1 and lends_to(problem, warm_start, choice)
                start = warm_start if lend else None
                outcome = self._attempt(
                    problem, choice, start, len(tried), started, searching, False
                )
                if isinstance(outcome, Trajectory):
                    return outcome
                failure = outcome
                if windows[-1] is None:
                    windows[-1] = self._window(problem, choice, failure)
        if failure is None:  # pragma: no cover - the first search returns at least one branch
            raise SolverError(self.solver, "no contact configuration to solve from")
        raised = self._strike_error(failure, problem, found, windows)
        raise raised from solver_cause(raised, failure)

    def _window(
        self, problem: PoolStrike, choice: ContactChoice, failure: SolverError | None
    ) -> WindowRatio | None:
        """The window check of a choice once a solve was found infeasible, else None.

        Whatever the choice's velocity ratio: the contact choice checks three configurations
        of the line, and its window can need more than the limits at a ratio of 0.75 (strike
        benchmark ball 15 at 1.2 m/s, second choice: 1.05). None too when the check has no
        answer (no IK start on the line, no finite point).
        """
        if failure is None or failure.status not in INFEASIBLE_STATUSES:
            return None
        self._in_budget(failure, "the window check")
        try:
            return self._window_check(problem, choice.q)
        except OptrajError:
            return None

    def _alone_error(
        self, failure: SolverError, problem: PoolStrike, choice: ContactChoice, *, searched: bool
    ) -> SolverError:
        """The error of a pool strike solved from one contact only (``contact_retries=0``).

        A window past the limits says nothing of other contacts, so the solver's error stays,
        with the window check's finding added; a searched ``choice`` also gets
        :func:`near_the_limit`'s hint (a warm start's contact has room by construction).
        """
        raised = near_the_limit(failure, problem, [choice]) if searched else failure
        window = self._window(problem, choice, failure)
        if window is None or not past_the_limits(window):
            return raised
        return detailed_failure(
            raised,
            f"from this contact configuration {window.describe()}; other contact "
            f"configurations (contact_retries > 0) may plan",
        )

    def _strike_error(
        self,
        failure: SolverError,
        problem: PoolStrike,
        choices: list[ContactChoice],
        windows: list[WindowRatio | None],
    ) -> OptrajError:
        """The error of a pool strike whose every solve failed.

        An :class:`InfeasibleError` when every choice's window needs more than the limits
        (``windows[i]`` is ``choices[i]``'s window check, None if it had none), else
        :func:`near_the_limit`'s.
        """
        if (
            failure.status not in INFEASIBLE_STATUSES
            or not windows
            or not all(past_the_limits(window) for window in windows)
        ):
            return near_the_limit(failure, problem, choices)
        best = min((w for w in windows if w is not None), key=lambda window: window.ratio)
        tried = (
            "the contact configuration tried"
            if len(choices) == 1
            else f"each of the {len(choices)} contact configurations tried"
        )
        remedy = "a slower strike or looser limits" if best.max_speed > 0.0 else "looser limits"
        return InfeasibleError(
            f"pool strike at {float(problem.speed):.3g} m/s: the strike window of {tried}, "
            f"with the approach into it and the stop after it, needs more than the joint "
            f"limits ({self.solver} status {failure.status!r}); {best.describe()}: {remedy} "
            f"may plan",
            limit=best.limit,
            joint=best.joint,
            required=best.required,
            allowed=best.allowed,
            max_speed=best.max_speed,
            found_by=WINDOW_CHECK,
        )

    def _attempt(
        self,
        problem: PoolStrike,
        choice: ContactChoice,
        warm_start: Trajectory | None,
        attempt: int,
        started: float,
        searching: float,
        from_warm_start: bool,
    ) -> Trajectory | SolverError:
        """Plan a pool strike from the ``attempt``-th contact choice (counted from 1).

        ``searching`` is the wall time of the contact choices so far [s].

        Returns:
            The trajectory, or the solver's error for the caller to try another choice.
        """
        try:
            traj = self._plan(problem, pool_spec(problem, choice, warm_start), warm_start)
        except SolverError as error:
            if error.status == BUDGET_SPENT:
                raise
            return error
        traj.metadata["contact_attempts"] = attempt
        traj.metadata["contact_from_warm_start"] = from_warm_start
        return stamp(traj, self.name, started, contact_time=searching)

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

    # -- rounds of solve, verify, refine -----------------------------------------------------

    def _weights(self, spec: Spec, *, time_only: bool = False) -> dict[str, float]:
        weights = {"time": 1.0} if time_only else dict(self.weights)
        robot = spec.robot
        if set(weights) == {"time"} and all(d is not None for d in spec.durations):
            weights = {"jerk": 1.0}  # nothing to shorten: the smoothest motion in the time
        if self.regularization > 0.0:
            weights["jerk"] = weights.get("jerk", 0.0) + self.regularization
            weights["grid"] = GRID_WEIGHT if spec.strike_phase < 0 else STRIKE_GRID_WEIGHT
            if robot.dof >= 7:
                weights["posture"] = self.regularization
        return weights

    def _rounds(
        self,
        problem: Any,
        spec: Spec,
        weights: dict[str, float],
        warm_start: Trajectory | None,
    ) -> Trajectory:
        torque_nodes: tuple[int, ...] = ()
        position_rows = self.position_rows is True
        shrink: FloatArray | None = None  # node bounds moved in, (nodes, 2, n) [rad or m]
        shrinks = 0
        strike_scale = 1
        saved = None if warm_start is None else warm_start.metadata.get("warm_start")
        if isinstance(saved, WarmStart) and len(saved.structure.intervals) == len(spec.names):
            # Same grid and torque rows as the previous solution, so its duals apply too.
            spec.intervals = saved.structure.intervals
            torque_nodes = saved.structure.torque_nodes
            position_rows = position_rows or saved.structure.position_rows
        torque_margin = self.torque_margin
        row_margins: FloatArray | None = None  # linear rows: per node and joint
        expansions = 0  # rounds in a row solved with linear rows
        solves: list[Trajectory] = []
        for round_ in range(1, ROUNDS + 1):
            built = self._build(
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
            traj = self._solve(built)
            solves.append(traj)
            # Nothing but the grid to change: no torque rows, no moved bounds, no new rows.
            plain = not built.compiled.structure.torque_nodes and shrink is None
            ratios = self._torque_ratios(traj, spec)
            more = [] if self.torque is False else self._torque_nodes(traj, ratios, built, spec)
            misses = self._strike_misses(traj, problem, spec)
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
                if self.torque_rows == "linear":
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
                self.solver, f"{unsettled} not settled", detail=f"after {round_} rounds"
            )
        what = "; ".join(
            f"{name} {value:.3g} {unit} (plans keep it within {allowed:.3g} {unit}, half the "
            f"tolerance)"
            for name, value, allowed, unit in misses
        )
        if ratios is not None and ratios[1].max() > 1.0:
            what += f"; torques up to {ratios[1].max():.3g} of their limits"
        intervals = built.compiled.structure.intervals[spec.strike_phase]
        raise SolverError(
            self.solver,
            "strike line not met between nodes",
            detail=f"with {intervals} strike intervals after {round_} rounds: {what}; a looser "
            f"tolerance or a faster strike (a shorter window) may pass",
        )

    @staticmethod
    def _torque_ratios(
        traj: Trajectory, spec: Spec
    ) -> tuple[FloatArray, FloatArray, FloatArray] | None:
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

    def _torque_nodes(
        self,
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
        settled = np.maximum(1.0 - 0.5 * self.torque_margin, fixed_ratios(spec))
        if np.all(np.abs(tau) / spec.limits.effort <= settled):
            return []
        knots = traj.breakpoints
        hot = np.unique(
            np.clip(
                np.searchsorted(knots, times[ratio > TORQUE_WATCH], "right") - 1, 0, len(knots) - 2
            )
        )
        nodes = set()
        for k in hot.tolist():
            nodes.update((k, k + 1))
        existing = set(built.compiled.structure.torque_nodes)
        return sorted(nodes - existing) or sorted(nodes)

    def _strike_misses(
        self, traj: Trajectory, problem: Any, spec: Spec
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

    # -- building ----------------------------------------------------------------------------

    def _grids(self, spec: Spec, strike_scale: int) -> tuple[PhaseGrid, ...]:
        grids = []
        for index, (name, fixed) in enumerate(zip(spec.names, spec.durations, strict=True)):
            guess_phase = spec.guess.phase(name)
            guess = max(guess_phase.duration, 1e-3) if fixed is None else fixed
            step = self.strike_step if index == spec.strike_phase else self.step
            if spec.intervals is not None:
                count = spec.intervals[index]
            elif isinstance(self.intervals, int):
                count = self.intervals
            elif isinstance(self.intervals, Mapping) and name in self.intervals:
                count = self.intervals[name]
            else:
                count = int(np.clip(5 * np.ceil(guess / step / 5.0), 5, 60))
                if fixed is None:  # room to grow: at least 1.25 x the guess at max_interval
                    count = max(count, int(5 * np.ceil(1.25 * guess / self.max_interval / 5.0)))
            if index == spec.strike_phase and strike_scale > 1:
                count = min(count * strike_scale, MAX_STRIKE_INTERVALS)
            if count > MAX_PHASE_INTERVALS:
                raise InvalidInputError(
                    f"phase {name!r} would need {count} intervals (its first guess lasts "
                    f"{guess:.3g} s, max_interval is {self.max_interval:.3g} s), more than "
                    f"{MAX_PHASE_INTERVALS}: raise max_interval or set fewer intervals",
                    name="max_interval" if spec.intervals is None else "intervals",
                )
            upper = count * self.max_interval if fixed is None else fixed
            if fixed is None and upper < guess:
                guess = upper
            grids.append(PhaseGrid(name, count, fixed, guess, upper))
        return tuple(grids)

    def _options(self) -> tuple[tuple[str, Any], ...]:
        options: dict[str, Any] = {"print_time": False}
        if self.solver == "ipopt":
            options.update(
                {
                    "ipopt.print_level": 0,
                    "ipopt.sb": "yes",
                    "ipopt.tol": self.tolerance,
                    "ipopt.constr_viol_tol": 1e-9,
                    "ipopt.max_iter": self.max_iterations,
                    "ipopt.mu_strategy": "monotone",
                    # MUMPS's own row and column scaling costs about a third of a solve on
                    # these KKT systems, whose rows are already scaled by the limits, and
                    # changes no iterate count (measured on the strike benchmark's shots).
                    "ipopt.mumps_permuting_scaling": 0,
                    "ipopt.mumps_scaling": 0,
                    # IPOPT refines every step at least once by default; these steps meet
                    # its residual test without it. Off: about 8 % less NLP time per
                    # iteration, the same iterates (20 strike shots cold and warm, A/B
                    # twice, identical iteration counts).
                    "ipopt.min_refinement_steps": 0,
                    # IPOPT's heuristics for problems that may be infeasible: while the
                    # violation is above 1e-3 (expect_infeasible_problem_ctol) and until the
                    # first restoration phase, the line search turns to restoration sooner
                    # (no watchdog or soft restoration), and restoration must cut the
                    # violation further before it ends. Measured with a fresh planner per
                    # shot on Sawyer pool strikes of the speed table's 10 balls: at 1.5 m/s
                    # the 6 that pass the contact choice but need more acceleration than the
                    # limits give on the line took 1.0 to 21.0 s (33.4 s in all) to their
                    # SolverError without them, 0.4 to 3.2 s (8.8 s) with them; the same
                    # iterates with and without on the first 30 benchmark shots at 1 m/s, 10
                    # at 0.03 and 0.3 m/s, the 18 of the 10 balls that plan at 1.2 and
                    # 1.35 m/s, and the test suite's 20 paddle4 strikes, 20 minimum-time and
                    # 10 minimum-jerk Sawyer moves and 10 youBot moves with a jerk weight.
                    "ipopt.expect_infeasible_problem": "yes",
                }
            )
        elif self.solver == "sqpmethod":
            options.update(
                {
                    "print_header": False,
                    "print_iteration": False,
                    "print_status": False,
                    "max_iter": self.max_iterations,
                    "qpsol_options": {"printLevel": "none"},
                }
            )
        options.update(self.solver_options)
        return freeze_options(options)

    def _compile(self, structure: Structure, robot: Robot) -> CompiledNLP:
        with self._lock:
            compiled = self._compiled.get(structure)
            if compiled is not None:
                return compiled
            model = self._models.get(robot.fingerprint)
            if model is None:
                model = self._models[robot.fingerprint] = SymbolicModel(robot)
        try:
            compiled = compile_nlp(structure, model)
        except RuntimeError as error:
            if not self.solver_options:
                raise
            raise InvalidInputError(
                f"solver_options {self.solver_options!r} were refused by the {self.solver} "
                f"plugin: {casadi_reason(str(error))}",
                name="solver_options",
            ) from error
        with self._lock:
            return self._compiled.setdefault(structure, compiled)

    def _build(
        self,
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
        grids = self._grids(spec, strike_scale or 1)
        intervals = tuple(g.intervals for g in grids)
        first = np.concatenate([[0], np.cumsum(intervals)]).astype(int)
        nodes = int(first[-1]) + 1
        linear = self.torque_rows == "linear"
        if self.torque is True or (linear and torque_nodes):
            torque_nodes = tuple(range(nodes))
        margin = self.torque_margin if torque_margin is None else torque_margin
        structure = Structure(
            robot=spec.robot.fingerprint,
            limits=structure_limits(spec.limits),
            tool_frame=spec.robot.tool_frame,
            intervals=intervals,
            free=tuple(g.duration is None for g in grids),
            free_grid=self.free_grid,
            strike_phase=spec.strike_phase,
            contact_node=int(first[spec.contact_phase + 1]) if spec.contact_phase >= 0 else -1,
            position_rows=self.position_rows is True if position_rows is None else position_rows,
            torque_nodes=tuple(n for n in torque_nodes if n < nodes),
            torque_rows=self.torque_rows,
            weights=tuple(sorted(weights.items())),
            margin=self.margin,
            torque_margin=0.0 if linear else margin,  # linear rows: in their coefficients
            solver=self.solver,
            options=self._options(),
        )
        compiled = self._compile(structure, spec.robot)
        layout = compiled.layout
        mid, half, vel, acc, _ = compiled.scale
        keep = 1.0 - self.margin

        lbx = np.empty(layout.size)
        ubx = np.empty(layout.size)
        for i, grid in enumerate(grids):
            index = slice(layout.first_node[i], layout.first_node[i + 1])
            if grid.duration is None:
                lbx[index], ubx[index] = MIN_INTERVAL, self.max_interval
            else:
                lbx[index] = ubx[index] = grid.duration / grid.intervals
        x_lower = np.concatenate([-np.ones(spec.limits.n), -keep * np.ones(2 * spec.limits.n)])
        lbx[layout.x_start : layout.u_start] = np.tile(x_lower, layout.nodes)
        ubx[layout.x_start : layout.u_start] = np.tile(-x_lower, layout.nodes)
        lbx[layout.u_start :] = -keep
        ubx[layout.u_start :] = keep
        if spec.strike_phase >= 0 and spec.contact is not None:
            caps = strike_caps(spec.contact.ratio, keep)
            for node in range(int(first[spec.strike_phase]), int(first[spec.strike_phase + 1]) + 1):
                for block, cap in ((1, caps[0]), (2, caps[1])):
                    index = layout.x_index(node, block)
                    lbx[index], ubx[index] = -cap, cap
        if shrink is not None:  # node position bounds moved in (fixed states override them)
            for node in range(layout.nodes):
                index = layout.x_index(node, 0)
                lbx[index] = -1.0 + shrink[node, 0] / half
                ubx[index] = 1.0 - shrink[node, 1] / half
        for fixed in spec.fixed:
            node = int(first[fixed.phase] if fixed.at == "start" else first[fixed.phase + 1])
            for block, value, scale, shift in (
                (0, fixed.q, half, mid),
                (1, fixed.qd, vel, 0.0),
                (2, fixed.qdd, acc, 0.0),
            ):
                if value is None:
                    continue
                tol = fixed.tolerance if block == 0 else 0.0
                index = layout.x_index(node, block)
                lbx[index] = (value - tol - shift) / scale
                ubx[index] = (value + tol - shift) / scale

        x0, lam_x0, lam_g0 = self._initial(spec, grids, compiled, lbx, ubx, warm_start)
        params = dict(spec.params)
        params["time_scale"] = sum(g.guess for g in grids)
        saved = None if warm_start is None else warm_start.metadata.get("warm_start")
        if lam_g0 is not None and isinstance(saved, WarmStart) and saved.time_scale:
            params["time_scale"] = saved.time_scale  # the multipliers' objective
        p = parameter_vector(**params)
        if linear:  # expanded about the initial point: the previous solution or the guess
            room = fixed_room(
                spec, first, structure.torque_nodes, margin if row_margins is None else row_margins
            )
            p = np.concatenate([p, torque_linearization(compiled, x0, room)])
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

    def _initial(
        self,
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
        mid, half, vel, acc, _ = compiled.scale
        x0 = np.zeros(layout.size)
        for i, grid in enumerate(grids):
            window = source.phase(grid.name)
            duration = window.duration if grid.duration is None else grid.duration
            x0[layout.first_node[i] : layout.first_node[i + 1]] = duration / grid.intervals
            times = np.linspace(window.t_start, window.t_end, grid.intervals + 1)
            sample = source.sample(times)
            first = int(layout.first_node[i])
            for j in range(grid.intervals + 1):
                node = first + j
                x0[layout.x_index(node, 0)] = (sample.q[j] - mid) / half
                x0[layout.x_index(node, 1)] = sample.qd[j] / vel
                x0[layout.x_index(node, 2)] = sample.qdd[j] / acc
        kept = {int(node) for node in layout.first_node}
        if spec.strike_phase >= 0:
            phase = spec.strike_phase
            kept.update(range(layout.first_node[phase], layout.first_node[phase + 1] + 1))
        return np.clip(integrable(x0, layout, compiled.scale, sorted(kept)), lbx, ubx), None, None

    # -- solving -----------------------------------------------------------------------------

    def _call(
        self, built: OptimalControlProblem, solver: ca.Function, args: dict[str, Any]
    ) -> SolverCall:
        """One solver call.

        Its ``error`` is set when the solver raised, did not succeed, or left a constraint
        group violated by more than 1e-6 (scaled).

        Raises:
            SolverError: Status :data:`BUDGET_SPENT`: the plan's deadline passed before or
                during the call.
        """
        self._in_budget(None, "a solve")
        with built.compiled.lock:
            started = time.perf_counter()
            try:
                result = solver(**args)
            except RuntimeError as error:  # the plugin raised instead of returning a status
                stats = solver.stats()
                failure = SolverError(
                    self.solver,
                    str(stats.get("return_status", "exception")),
                    iterations=int(stats.get("iter_count", -1)),
                    detail=casadi_reason(str(error)),
                )
                failure.__cause__ = error
                wall = time.perf_counter() - started
                return SolverCall(np.zeros(0), {}, stats, wall, math.inf, failure)
            wall = time.perf_counter() - started
            stats = solver.stats()
        w = np.asarray(result["x"]).reshape(-1)
        violations = built._violations(w)
        worst = max(violations.values())
        failure = None
        if not stats.get("success", False) or not np.all(np.isfinite(w)) or worst > 1e-6:
            failure = SolverError(
                self.solver,
                str(stats.get("return_status", "unknown")),
                iterations=int(stats.get("iter_count", -1)),
                detail=diagnosis(built, w) if np.all(np.isfinite(w)) else "no finite point",
            )
            self._in_budget(failure, "a solve")
        return SolverCall(w, result, stats, wall, worst, failure)

    def _in_budget(self, failure: SolverError | None, what: str) -> None:
        """Raise the budget's ``SolverError`` when this plan's deadline has passed.

        Args:
            failure: The last solver failure, whose finding the error repeats, or None.
            what: What the deadline stopped, e.g. ``"a solve"``.
        """
        if time_left() > 0.0:
            return
        found = f"; the last solve failed: {failure}" if failure is not None else ""
        raise SolverError(
            self.solver,
            BUDGET_SPENT,
            iterations=None if failure is None else failure.iterations,
            detail=f"the plan took its time_budget of {self._budget():.4g} s, which stopped "
            f"{what}{found}; a larger time_budget, looser limits or an easier problem may plan",
        )

    def _solve(self, built: OptimalControlProblem) -> Trajectory:
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
            call = self._call(built, compiled.warm(), warm)
            if call.error is not None:
                # The multipliers led nowhere within WARM_ITERATIONS (a previous solution
                # whose active set is far from this problem's): solve again from the same
                # primal point with the cold solver's fresh barrier.
                abandoned, call = call, self._call(built, compiled.solver, args)
        else:
            call = self._call(built, compiled.solver, args)
        if call.error is not None:
            raise call.error
        w, stats = call.w, call.stats
        dropped = (0, 0.0, 0.0) if abandoned is None else abandoned.spent()
        traj = solution_trajectory(built, w)
        traj.metadata.update(
            {
                "solver": self.solver,
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
                    float(built.p[0]),  # time_scale, the first parameter
                ),
            }
        )
        if built.contact is not None:
            traj.metadata["contact_speed_ratio"] = built.contact.ratio
            traj.metadata["contact_max_speed"] = built.contact.max_speed
            traj.metadata["contact_configuration"] = np.array(built.contact.q, dtype=float)
        return traj

    # -- problems ------------------------------------------------------------------------------

    def _spec(self, problem: Any) -> Spec:
        """The problem's phases, fixed states and guess; its fixed states' torques checked.

        Raises:
            InfeasibleError: A state the problem fixes (start, goal) needs more torque than
                the effort limits
                (:func:`planners.time_optimal.lower_bound.check_state_torques`), unless
                ``torque=False``; a strike no contact configuration can make.
        """
        if isinstance(problem, PointToPoint):
            problem.require_motion(self.name)
            return self._held(point_to_point_spec(problem))
        if isinstance(problem, Waypoints):
            problem.require_motion(self.name)
            return self._held(waypoints_spec(problem))
        if isinstance(problem, (PoolStrike, PaddleStrike)):
            self._strike_start_held(problem)
            started = time.perf_counter()
            # The margin the NLP keeps from the velocity limits: a contact past it is refused
            # here, with its binding joint, instead of by an infeasible solve.
            choice = choose_contact(problem, candidates=self.contact_candidates, margin=self.margin)
            searched = time.perf_counter() - started
            spec = (
                pool_spec(problem, choice)
                if isinstance(problem, PoolStrike)
                else paddle_spec(problem, choice)
            )
            spec.contact_time = searched
            return spec
        raise InvalidInputError(
            f"OptimalControl plans a PointToPoint, Waypoints, PoolStrike or PaddleStrike, got "
            f"{type(problem).__name__}",
            name="problem",
        )

    def _held(self, spec: Spec) -> Spec:
        """``spec``, once the torques of its fully fixed states are within the effort limits.

        Raises:
            InfeasibleError: One needs more (unless ``torque=False``, which plans without
                torque limits).
        """
        if self.torque is not False:
            last = len(spec.names) - 1
            states = [
                (fixed_name(f, last), f.q, f.qd, f.qdd)
                for f in spec.fixed
                if f.q is not None and f.qd is not None and f.qdd is not None and not f.tolerance
            ]
            check_state_torques(spec.robot, spec.limits, states)
        return spec

    def _strike_start_held(self, problem: PoolStrike | PaddleStrike) -> None:
        """Check a strike's start at rest before its contact choice (:meth:`_held`)."""
        if self.torque is not False:
            zeros = zero_vector(problem.limits.n)
            start = ("the start state (at rest)", problem.q_start, zeros, zeros)
            check_state_torques(problem.robot, problem.limits, [start])
