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

import dataclasses
import math
import re
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    WINDOW_CHECK,
    InfeasibleError,
    InvalidInputError,
    MissingDependencyError,
    OptrajError,
    PathJumpError,
    SolverError,
    UnreachableError,
)
from optraj.planners.base import CompiledCache, stamp
from optraj.planners.checker import RELATIVE_SLACK
from optraj.planners.ocp.transcription import (
    TORQUE_ROWS,
    CompiledNLP,
    Layout,
    Structure,
    compile_nlp,
    deadline,
    freeze_options,
    jerk_step,
    parameter_vector,
    structure_limits,
    time_left,
    torque_linearization,
)
from optraj.planners.profiles.time_scaling import quintic_coefficients
from optraj.planners.strike.contact import (
    BRANCH_SPREAD,
    HEADROOM,
    MAX_CANDIDATES,
    ContactChoice,
    choose_contact,
    contact_choices,
    contact_near,
)
from optraj.planners.strike.time_optimal_strike import strike_line
from optraj.planners.strike.window_check import WindowCheck, WindowRatio
from optraj.planners.time_optimal.lower_bound import check_state_torques, joint_min_durations
from optraj.planners.time_optimal.ruckig_planner import state_to_state, stop
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PaddleStrike, PointToPoint, PoolStrike, Waypoints
from optraj.problems.common import normal_pair
from optraj.robots import JointLimits, Robot, SymbolicModel
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import (
    MAX_DURATION,
    as_choice,
    as_count,
    as_duration,
    as_flag,
    as_number,
    as_positive,
    as_vector,
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

#: Objective terms that can be weighted.
OBJECTIVES = ("time", "jerk", "effort")
#: CasADi NLP plugins that can be named (the installed CasADi decides which load). Left
#: out, as measured with CasADi 3.8.2: fatrop (the transcription is not in its stage-wise
#: layout: three times slower than IPOPT on a paddle4 move, and on the pool strike NLP it
#: hangs inside its first iterations) and blocksqp (it needs HSL's MA27, which CasADi's
#: wheels do not ship).
#: sqpmethod (qpOASES) plans small problems (a paddle4 move in 0.8 s, IPOPT 0.08 s) but
#: did not finish a pool strike in 90 s.
SOLVERS = ("ipopt", "sqpmethod", "bonmin", "knitro", "snopt", "worhp")
#: Torques above this fraction of their limit get rows at the surrounding nodes [-].
TORQUE_WATCH = 0.9
#: Points per interval at which the torques are evaluated after a solve.
TORQUE_POINTS = 4
#: Rounds of solve, verify, refine (linear torque rows converge in a few warm rounds).
ROUNDS = 8
#: Weight of the term that keeps neighbouring intervals of a free phase alike [-]: small, so
#: that the nodes of a minimum-time joint move can sit on its jerk switches (within 0.2 % of
#: the lower bound; 1.0 leaves some 0.2 % above it).
GRID_WEIGHT = 1e-2
#: The same weight in a pool strike. Measured on 20 benchmark shots (IPOPT, minimum time):
#: 1e-2 gave a median NLP time of 284 ms (p95 815 ms); 1.0 gave 161 ms (p95 272 ms) for
#: motions 0.3 % longer; a uniform grid (``free_grid=False``) 128 ms for 1.2 % longer.
STRIKE_GRID_WEIGHT = 1.0
#: Shortest interval of a free phase [s].
MIN_INTERVAL = 1e-4
#: Most intervals of a strike phase after refinement.
MAX_STRIKE_INTERVALS = 120
#: The phases of the problems planned here (a Waypoints problem's are "segment 1", ...).
PHASE_NAMES = ("move", "approach", "strike", "stop")
#: Most intervals a phase may have: far more than any strike or move needs (the defaults give
#: 5 to 60), and an NLP that a solver takes minutes over; a grid past it is refused.
MAX_PHASE_INTERVALS = 400
#: Rounds that move node position bounds in before position rows come in.
POSITION_SHRINKS = 3
#: Extra room a moved node bound keeps beyond the excess it answers [rad or m].
SHRINK_EXTRA = 1e-6
#: Largest fraction of a joint's range a node bound moves in [-].
MAX_SHRINK = 0.25
#: Weight, against 1 at the other nodes, with which a sampled guess keeps its states at phase
#: ends and on the strike line when it is fitted to the dynamics rows (:func:`_integrable`).
#: Cold iterations on 2 x 40 strike benchmark shots, 95th percentile: 62 and 53 unfitted; 50
#: and 47 at 30; 50 at 1e3, which left one shot at 86 (a heavy weight over-constrains short
#: phases, whose both ends it holds).
KEPT_NODE_WEIGHT = 30.0
#: Weight of the (scaled) jerks in that fit: small, it only settles what the states leave free.
FIT_JERK_WEIGHT = 1e-3
#: Strike-phase node velocities stay within this multiple of the contact choice's ratio (the
#: largest fraction of a velocity limit the line needs) [-]; see :func:`strike_caps`.
STRIKE_VELOCITY_ROOM = 3.0
#: Strike-phase node accelerations stay within this multiple of the ratio squared (the
#: accelerations the line needs grow with the square of its speed) [-]. Tuned on Sawyer
#: with ``OptimalControl("time")`` on the first 20 balls of ``benchmarks/strike.py`` at each
#: speed, each planned after an untimed plan of it that compiles its NLPs. Without bounds:
#: at 0.1 m/s 18/20 shots needed a finer strike grid (median plan 1.04 s), and the first 8
#: balls at 0.03 m/s all failed (a SolverError after 8 rounds, about 9 s each). With 3 and
#: 10: 20/20 at 0.03, 0.1, 0.2, 0.5 and 1 m/s, median plans 0.47, 0.31, 0.19, 0.12 and 0.11 s.
#: Motions were up to 1 % longer at 0.1 m/s, within 0.01 % at 0.5 m/s and the same at 1 m/s
#: (ratios 0.52 to 0.90 there, where both bounds lie past the limits). A factor of 20 left
#: 4/20 shots at 0.1 m/s needing a finer grid.
STRIKE_ACCELERATION_ROOM = 10.0
#: A pool strike whose contact configurations all need more than this fraction of a velocity
#: limit is near the fastest speed they allow: once the NLP is found infeasible, the error says
#: so [-]. The contact choice's own threshold for room to spare.
TIGHT_RATIO = HEADROOM
#: The solver statuses of an NLP found (locally) infeasible.
INFEASIBLE_STATUSES = frozenset({"Infeasible_Problem_Detected", "Restoration_Failed"})
#: Default wall-time budget of one plan [s] (``OptimalControl(time_budget=...)``). Plans of
#: the strike benchmark take 0.1 to 2.3 s, the slowest feasible strikes measured (0.07 m/s
#: with effort limits at 22 % of Sawyer's) about 30 s; past a minute a solve is lost in a
#: problem it will not settle.
TIME_BUDGET = 60.0
#: :attr:`optraj.errors.SolverError.status` of a plan stopped because its time budget is spent.
BUDGET_SPENT = "time budget spent"
#: IK samples of the strike line in a pool strike's first guess (:func:`_window_guess`).
LINE_SAMPLES = 10
#: The same when the joints jump between those samples by more than
#: :func:`planners.profiles.cartesian.follow_tool_path`'s threshold.
LINE_SAMPLES_FINE = 40


@dataclass(frozen=True)
class PhaseGrid:
    """The time grid of one phase.

    Attributes:
        name: Phase name (as in the trajectory's phases).
        intervals: Equal intervals of the phase.
        duration: Fixed duration [s], or None when the solver chooses it.
        guess: Initial duration [s].
        upper: Largest duration allowed [s] (``intervals * max_interval`` for a free phase).
    """

    name: str
    intervals: int
    duration: float | None
    guess: float
    upper: float


@dataclass(frozen=True, eq=False)
class WarmStart:
    """A solution's primal and dual values, to warm start a solve of the same structure.

    ``time_scale`` [s] is the objective's divisor in that solve: a solve started from these
    multipliers keeps it, so that they still fit its objective.
    """

    structure: Structure
    w: FloatArray
    lam_x: FloatArray
    lam_g: FloatArray
    time_scale: float | None = None


@dataclass(eq=False)
class OptimalControlProblem:
    """A built optimal control problem, ready to solve and open for inspection.

    Attributes:
        problem: The problem it was built from.
        compiled: The CasADi NLP (``compiled.w``, ``.f``, ``.g``, ``.p``, ``.groups``) and
            its solver.
        grids: The phases' time grids.
        x0: Initial guess of the decision vector.
        lbx: Lower bounds of the decision vector (fixed states have equal bounds).
        ubx: Upper bounds.
        p: Parameter values (see :data:`planners.ocp.transcription.PARAMETERS`).
        lam_x0: Initial bound multipliers (a warm start), or None.
        lam_g0: Initial constraint multipliers, or None.
        contact: The chosen contact configuration of a strike, or None.
        guess: The trajectory the initial guess was sampled from.
    """

    problem: Any
    compiled: CompiledNLP
    grids: tuple[PhaseGrid, ...]
    x0: FloatArray
    lbx: FloatArray
    ubx: FloatArray
    p: FloatArray
    lam_x0: FloatArray | None
    lam_g0: FloatArray | None
    contact: ContactChoice | None
    guess: Trajectory

    @property
    def variables(self) -> int:
        """Number of decision variables."""
        return int(self.x0.size)

    @property
    def constraints(self) -> int:
        """Number of constraint rows."""
        return int(self.compiled.lbg.size)

    def violations(self, w: FloatArray) -> dict[str, float]:
        """Largest bound excess of each constraint group (and ``"bounds"``) at ``w``.

        Raises:
            InvalidInputError: ``w`` is not a finite vector of :attr:`variables` entries.
        """
        return self._violations(as_vector(w, "w", self.variables))

    def _violations(self, w: FloatArray) -> dict[str, float]:
        """:meth:`violations` of a solver's point, which may hold NaN (then so do they)."""
        g = np.asarray(self.compiled.constraint_values(w, self.p)).reshape(-1)
        excess = np.maximum(self.compiled.lbg - g, g - self.compiled.ubg)
        result = {"bounds": float(np.max(np.maximum(self.lbx - w, w - self.ubx), initial=0.0))}
        names, order, starts = self.compiled.group_order
        if names:
            peaks = np.maximum(np.maximum.reduceat(excess[order], starts), 0.0)
            result.update(zip(names, peaks.tolist(), strict=True))
        return result


# ------------------------------------------------------------------------------ the spec


@dataclass
class _Fixed:
    """A node state pinned by bounds: ``phase`` start or end; None entries stay free."""

    phase: int
    at: str
    q: FloatArray | None
    qd: FloatArray | None
    qdd: FloatArray | None
    tolerance: float = 0.0


@dataclass
class _Spec:
    """A problem turned into phases, fixed states, parameters and a first guess."""

    robot: Robot
    limits: JointLimits
    names: tuple[str, ...]
    durations: tuple[float | None, ...]
    guess: Trajectory
    fixed: list[_Fixed]
    params: dict[str, Any] = field(default_factory=dict)
    strike_phase: int = -1
    contact_phase: int = -1
    contact: ContactChoice | None = None
    intervals: tuple[int, ...] | None = None  # grid forced by a warm start
    contact_time: float = 0.0  # wall time of the contact choice [s]


def _objective(objective: str | Mapping[str, float]) -> dict[str, float]:
    if isinstance(objective, str):
        as_choice(objective, "objective", OBJECTIVES)
        return {objective: 1.0}
    if not isinstance(objective, Mapping) or not objective:
        raise InvalidInputError(
            f"objective must be one of {OBJECTIVES} or a mapping of weights, got {objective!r}",
            name="objective",
        )
    weights: dict[str, float] = {}
    for key, value in objective.items():
        as_choice(key, "objective term", OBJECTIVES)
        weight = as_number(value, f"objective weight {key!r}", minimum=0.0)
        if weight > 0.0:
            weights[key] = weight
    if not weights:
        raise InvalidInputError("objective needs at least one weight > 0", name="objective")
    return weights


def _solver_name(solver: str) -> str:
    as_choice(solver, "solver", SOLVERS)
    if not ca.has_nlpsol(solver):
        raise MissingDependencyError(
            package=f"casadi with the {solver} plugin",
            extra="all",
            feature=f"OptimalControl(solver={solver!r})",
        )
    return solver


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
        self.weights = _objective(objective)
        self.objective = objective if isinstance(objective, str) else dict(self.weights)
        self.solver = _solver_name(solver)
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
        warm_start = _checked_warm_start(problem, warm_start)
        if isinstance(problem, PoolStrike):  # before any contact search (_spec checks others)
            self._strike_start_held(problem)
        tried: list[FloatArray] = []
        failure: SolverError | None = None
        # Re-planning from a previous pool solution: first its contact branch, if it still
        # has room (one local IK instead of the search).
        seeded = None
        searching = 0.0  # the contact choices' wall time [s]
        if self.reuse_contact and isinstance(problem, PoolStrike):
            seeded = _contact_from(problem, warm_start, self.margin)
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
                raise raised from _cause(raised, outcome)
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
                raise raised from _cause(raised, error)
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
                if _past_the_limits(window):
                    continue
                # None after a seeded try, or for a choice on another branch than its own.
                lend = len(tried) == 1 and _lends_to(problem, warm_start, choice)
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
        raise raised from _cause(raised, failure)

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
        :func:`_near_the_limit`'s hint (a warm start's contact has room by construction).
        """
        raised = _near_the_limit(failure, problem, [choice]) if searched else failure
        window = self._window(problem, choice, failure)
        if window is None or not _past_the_limits(window):
            return raised
        return _detailed(
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
        :func:`_near_the_limit`'s.
        """
        if (
            failure.status not in INFEASIBLE_STATUSES
            or not windows
            or not all(_past_the_limits(window) for window in windows)
        ):
            return _near_the_limit(failure, problem, choices)
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
            traj = self._plan(problem, _pool(problem, choice, warm_start), warm_start)
        except SolverError as error:
            if error.status == BUDGET_SPENT:
                raise
            return error
        traj.metadata["contact_attempts"] = attempt
        traj.metadata["contact_from_warm_start"] = from_warm_start
        return stamp(traj, self.name, started, contact_time=searching)

    def _plan(self, problem: Any, spec: _Spec, warm_start: Trajectory | None) -> Trajectory:
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
            return _totals(traj, [timed, traj])
        return self._rounds(problem, spec, weights, warm_start)

    def build(self, problem: Any, warm_start: Trajectory | None = None) -> OptimalControlProblem:
        """The NLP of a problem with its bounds and initial guess, not yet solved.

        With an objective that has no time term, free durations stay free here (the
        two-step solve of :meth:`plan` fixes them). With ``position_rows="auto"`` the NLP is
        the first round's: positions bounded at the nodes only (:meth:`plan` checks them
        between nodes and solves again with the rows when one passes its limit).
        """
        warm_start = _checked_warm_start(problem, warm_start)
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

    def _weights(self, spec: _Spec, *, time_only: bool = False) -> dict[str, float]:
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
        spec: _Spec,
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
            excess = None if position_rows else _position_excess(traj, spec.limits)
            positions_ok = excess is None or not excess.any()
            if not more and strike_ok and positions_ok:
                _totals(traj, solves)
                traj.metadata["rounds"] = round_
                traj.metadata["torque_rows"] = len(built.compiled.structure.torque_nodes)
                traj.metadata["position_rows"] = position_rows
                return traj
            if not positions_ok and shrinks < POSITION_SHRINKS:
                # A piece passed a limit between nodes: its nodes' bounds move in, warm.
                shrink = _shrunk(shrink, excess, spec.limits)
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
                        row_margins = _tightened(
                            row_margins, ratios[2] / spec.limits.effort, _fixed_ratios(spec)
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
        traj: Trajectory, spec: _Spec
    ) -> tuple[FloatArray, FloatArray, FloatArray] | None:
        """Torques at TORQUE_POINTS per interval: (times, worst |tau| / effort, tau).

        None when the effort limits are not all finite (nothing to watch).
        """
        effort = spec.limits.effort
        if not np.all(np.isfinite(effort)):
            return None
        times = _dense_times(traj, TORQUE_POINTS)
        s = traj.sample(times)
        tau = spec.robot.inverse_dynamics(s.q, s.qd, s.qdd)
        return times, np.max(np.abs(tau) / effort, axis=1), tau

    def _torque_nodes(
        self,
        traj: Trajectory,
        ratios: tuple[FloatArray, FloatArray, FloatArray] | None,
        built: OptimalControlProblem,
        spec: _Spec,
    ) -> list[int]:
        """Nodes to add torque rows at: around intervals where a torque nears its limit.

        None once every torque keeps within ``1 - torque_margin / 2`` of its limit, or within
        what a fixed state of the problem itself needs of that joint's limit, if more (a
        start holding 99 % of a limit against gravity: :func:`_fixed_room`).
        """
        if ratios is None:
            return []
        times, ratio, tau = ratios
        settled = np.maximum(1.0 - 0.5 * self.torque_margin, _fixed_ratios(spec))
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
        self, traj: Trajectory, problem: Any, spec: _Spec
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

    def _grids(self, spec: _Spec, strike_scale: int) -> tuple[PhaseGrid, ...]:
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
                f"plugin: {_casadi_reason(str(error))}",
                name="solver_options",
            ) from error
        with self._lock:
            return self._compiled.setdefault(structure, compiled)

    def _build(
        self,
        problem: Any,
        spec: _Spec,
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
            room = _fixed_room(
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
        spec: _Spec,
        grids: tuple[PhaseGrid, ...],
        compiled: CompiledNLP,
        lbx: FloatArray,
        ubx: FloatArray,
        warm_start: Trajectory | None,
    ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
        """Initial primal (and dual) values: a previous solution, or a guess at the nodes.

        A guess is sampled at the nodes and fitted to the dynamics rows (:func:`_integrable`).
        """
        if warm_start is not None:
            saved = warm_start.metadata.get("warm_start")
            if isinstance(saved, WarmStart):
                lam_g = _constraint_duals(saved, compiled)
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
        return np.clip(_integrable(x0, layout, compiled.scale, sorted(kept)), lbx, ubx), None, None

    # -- solving -----------------------------------------------------------------------------

    def _call(
        self, built: OptimalControlProblem, solver: ca.Function, args: dict[str, Any]
    ) -> _Call:
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
                    detail=_casadi_reason(str(error)),
                )
                failure.__cause__ = error
                wall = time.perf_counter() - started
                return _Call(np.zeros(0), {}, stats, wall, math.inf, failure)
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
                detail=_diagnosis(built, w) if np.all(np.isfinite(w)) else "no finite point",
            )
            self._in_budget(failure, "a solve")
        return _Call(w, result, stats, wall, worst, failure)

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
        abandoned: _Call | None = None
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
        traj = _trajectory(built, w)
        traj.metadata.update(
            {
                "solver": self.solver,
                "status": "ok",
                "solver_status": str(stats.get("return_status", "unknown")),
                "iterations": int(stats.get("iter_count", -1)) + dropped[0],
                "nlp_time": call.wall + dropped[1],
                "evaluation_time": _evaluation_time(stats) + dropped[2],
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

    def _spec(self, problem: Any) -> _Spec:
        """The problem's phases, fixed states and guess; its fixed states' torques checked.

        Raises:
            InfeasibleError: A state the problem fixes (start, goal) needs more torque than
                the effort limits
                (:func:`planners.time_optimal.lower_bound.check_state_torques`), unless
                ``torque=False``; a strike no contact configuration can make.
        """
        if isinstance(problem, PointToPoint):
            problem.require_motion(self.name)
            return self._held(_point_to_point(problem))
        if isinstance(problem, Waypoints):
            problem.require_motion(self.name)
            return self._held(_waypoints(problem))
        if isinstance(problem, (PoolStrike, PaddleStrike)):
            self._strike_start_held(problem)
            started = time.perf_counter()
            # The margin the NLP keeps from the velocity limits: a contact past it is refused
            # here, with its binding joint, instead of by an infeasible solve.
            choice = choose_contact(problem, candidates=self.contact_candidates, margin=self.margin)
            searched = time.perf_counter() - started
            spec = (
                _pool(problem, choice)
                if isinstance(problem, PoolStrike)
                else _paddle(problem, choice)
            )
            spec.contact_time = searched
            return spec
        raise InvalidInputError(
            f"OptimalControl plans a PointToPoint, Waypoints, PoolStrike or PaddleStrike, got "
            f"{type(problem).__name__}",
            name="problem",
        )

    def _held(self, spec: _Spec) -> _Spec:
        """``spec``, once the torques of its fully fixed states are within the effort limits.

        Raises:
            InfeasibleError: One needs more (unless ``torque=False``, which plans without
                torque limits).
        """
        if self.torque is not False:
            last = len(spec.names) - 1
            states = [
                (_fixed_name(f, last), f.q, f.qd, f.qdd)
                for f in spec.fixed
                if f.q is not None and f.qd is not None and f.qdd is not None and not f.tolerance
            ]
            check_state_torques(spec.robot, spec.limits, states)
        return spec

    def _strike_start_held(self, problem: PoolStrike | PaddleStrike) -> None:
        """Check a strike's start at rest before its contact choice (:meth:`_held`)."""
        if self.torque is not False:
            zeros = _zeros(problem.limits.n)
            start = ("the start state (at rest)", problem.q_start, zeros, zeros)
            check_state_torques(problem.robot, problem.limits, [start])


def _fixed_room(
    spec: _Spec, first: NDArray[np.int_], nodes: tuple[int, ...], margin: float | FloatArray
) -> float | FloatArray:
    """Torque row margins that a fully fixed state's own torques fit within.

    The margin keeps room below the effort limits for the linear rows' expansion error and
    for peaks between nodes; at a node whose state the problem fixes the torques are what
    they are, and a margin past them would make the NLP infeasible at that node alone (a
    start at rest holding 99 % of a limit against gravity, with a margin of 3 %).

    Args:
        spec: The problem's spec (its fixed states).
        first: First node of each phase, and the last node, shape (phases + 1,).
        nodes: The nodes with torque rows.
        margin: One margin for every row, or one per row node and joint, shape
            (len(nodes), n) [-].

    Returns:
        ``margin``, or per row node and joint with each fixed node's margin at most
        ``1 - |tau| / effort`` there (at least 0).
    """
    index = {node: i for i, node in enumerate(nodes)}
    room: FloatArray | None = None
    for fixed in spec.fixed:
        if fixed.q is None or fixed.qd is None or fixed.qdd is None or fixed.tolerance:
            continue
        node = int(first[fixed.phase] if fixed.at == "start" else first[fixed.phase + 1])
        if node not in index:
            continue
        tau = spec.robot.inverse_dynamics(fixed.q, fixed.qd, fixed.qdd)
        left = np.maximum(1.0 - np.abs(tau) / spec.limits.effort, 0.0)
        if room is None:
            room = np.array(np.broadcast_to(margin, (len(nodes), spec.limits.n)), dtype=float)
        room[index[node]] = np.minimum(room[index[node]], left)
    return margin if room is None else room


def _fixed_ratios(spec: _Spec) -> FloatArray:
    """Each joint's largest ``|tau| / effort`` over the problem's fully fixed states [-], (n,)."""
    ratios = np.zeros(spec.limits.n)
    for fixed in spec.fixed:
        if fixed.q is None or fixed.qd is None or fixed.qdd is None or fixed.tolerance:
            continue
        tau = spec.robot.inverse_dynamics(fixed.q, fixed.qd, fixed.qdd)
        ratios = np.maximum(ratios, np.abs(tau) / spec.limits.effort)
    return ratios


def _fixed_name(fixed: _Fixed, last: int) -> str:
    """A fixed state in words: ``"the start state (at rest)"``, ``"the goal state"`` ..."""
    if fixed.at == "start" and fixed.phase == 0:
        name = "the start state"
    elif fixed.at == "end" and fixed.phase == last:
        name = "the goal state"
    else:  # pragma: no cover - the problems fix no other full state
        name = f"the state at the {fixed.at} of phase {fixed.phase}"
    moving = np.any(np.asarray(fixed.qd) != 0.0) or np.any(np.asarray(fixed.qdd) != 0.0)
    return name if moving else f"{name} (at rest)"


def strike_caps(ratio: float, keep: float = 1.0) -> tuple[float, float]:
    """Bounds of the strike nodes' joint velocities and accelerations, fractions of the limits.

    Args:
        ratio: The largest fraction of a joint velocity limit the strike line needs at the
            requested speed (:attr:`planners.strike.contact.ContactChoice.ratio`), >= 0 [-].
        keep: The bound without a cap, 1 minus the planner's margin, in (0, 1] [-].

    Returns:
        ``(velocity, acceleration)``: :data:`STRIKE_VELOCITY_ROOM` times ``ratio`` and
        :data:`STRIKE_ACCELERATION_ROOM` times its square, each at most ``keep`` [-].
        The 99 benchmark shots at 1 m/s that Sawyer can strike need ratios of 0.52 to 0.90,
        so the caps bind only in slower strikes.

    Raises:
        InvalidInputError: A ratio that is not a finite number >= 0, or ``keep`` outside
            (0, 1].
    """
    value = as_number(ratio, "ratio", minimum=0.0)
    room = as_number(keep, "keep", minimum=0.0, maximum=1.0, open_minimum=True)
    return (
        min(room, STRIKE_VELOCITY_ROOM * value),
        min(room, STRIKE_ACCELERATION_ROOM * value * value),
    )


def _tightened(
    margins: FloatArray,
    ratio: FloatArray,
    fixed: FloatArray | float = 0.0,
    per_interval: int = TORQUE_POINTS,
) -> FloatArray:
    """Torque row margins after a round whose dense torques broke their limits.

    Args:
        margins: Margins of the rows at every node, shape (K + 1, n) [-].
        ratio: Signed torque over effort limit at ``per_interval`` points per interval and
            the last node (as :func:`_dense_times`), shape (per_interval K + 1, n) [-].
        fixed: Per joint, the share of its limit a fixed state of the problem needs
            (:func:`_fixed_ratios`), shape (n,) [-]: a peak up to it is no excess.
        per_interval: Points per interval in ``ratio``.

    Returns:
        The margins of both end nodes of an interval whose peak passes ``1 - margin / 2``
        (and ``fixed``) raised by that excess plus 0.005, at most 0.5.
    """
    size = np.abs(ratio)
    intervals = margins.shape[0] - 1
    inner = size[:-1].reshape(intervals, per_interval, -1).max(axis=1)
    peaks = np.maximum(inner, size[per_interval::per_interval])  # (K, n), ends included
    excess = peaks - np.maximum(1.0 - 0.5 * np.minimum(margins[:-1], margins[1:]), fixed)
    bump = np.where(excess > 0.0, excess + 0.005, 0.0)
    raised = margins.copy()
    raised[:-1] = np.maximum(raised[:-1], margins[:-1] + bump)
    raised[1:] = np.maximum(raised[1:], margins[1:] + bump)
    return np.minimum(raised, 0.5)


def _constraint_duals(saved: WarmStart, compiled: CompiledNLP) -> FloatArray | None:
    """A solution's constraint multipliers for ``compiled``, or None when they do not apply.

    They apply to the same structure, and to one that differs only in its torque rows
    (those come last, n per node): a torque node's multipliers carry over where it had
    rows before, new rows start at zero.
    """
    old, new = saved.structure, compiled.structure
    if old == new:
        return saved.lam_g
    same_rows = dataclasses.replace(
        old,
        torque_nodes=new.torque_nodes,
        torque_rows=new.torque_rows,
        torque_margin=new.torque_margin,
    )
    if same_rows != new:
        return None
    n = compiled.layout.n
    base = saved.lam_g.size - n * len(old.torque_nodes)
    lam_g = np.zeros(compiled.lbg.size)
    if base < 0 or base + n * len(new.torque_nodes) != lam_g.size:
        return None
    lam_g[:base] = saved.lam_g[:base]
    before = {node: i for i, node in enumerate(old.torque_nodes)}
    for i, node in enumerate(new.torque_nodes):
        if node in before:
            j = before[node]
            lam_g[base + n * i : base + n * (i + 1)] = saved.lam_g[
                base + n * j : base + n * (j + 1)
            ]
    return lam_g


#: Names of the state parts the rows of :class:`planners.ocp.transcription.CompiledNLP` label.
_PARTS = ("position", "velocity", "acceleration")
#: A limit counts as binding at a solver's point when it uses this fraction of its bound [-].
BINDING = 0.995


def _diagnosis(built: OptimalControlProblem, w: FloatArray) -> str:
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


def _casadi_reason(message: str) -> str:
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
class _Call:
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
        return iterations, self.wall, _evaluation_time(self.stats)


def _totals(traj: Trajectory, solves: list[Trajectory]) -> Trajectory:
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


def _evaluation_time(stats: Mapping[str, Any]) -> float:
    """Wall time [s] a CasADi solver spent evaluating the NLP's functions and derivatives.

    The sum of the solver's ``t_wall_nlp_*`` statistics (objective, constraints, their
    gradients and Jacobian, the Lagrangian's Hessian); the rest of a solve's time is the
    solver's own (for IPOPT mostly its sparse linear algebra).
    """
    return float(
        sum(float(v) for k, v in stats.items() if k.startswith("t_wall_nlp_") and v is not None)
    )


def _shrunk(shrink: FloatArray | None, excess: FloatArray, limits: JointLimits) -> FloatArray:
    """Node bounds moved in after pieces passed a position limit between their nodes.

    Args:
        shrink: Moves so far, shape (K + 1, 2, n) [rad or m] (lower bound raised, upper
            lowered), or None.
        excess: :func:`_position_excess` of the last solution, shape (K, 2, n).
        limits: The joint limits.

    Returns:
        Both end nodes of a piece that passed a limit keep twice that excess (plus
        :data:`SHRINK_EXTRA`) more room on that side (once is seldom enough: the piece
        moves with its nodes), at most :data:`MAX_SHRINK` of the joint's range.
    """
    moved = np.zeros((excess.shape[0] + 1, *excess.shape[1:])) if shrink is None else shrink
    bump = np.where(excess > 0.0, 2.0 * excess + SHRINK_EXTRA, 0.0)
    raised = moved.copy()
    raised[:-1] = np.maximum(raised[:-1], moved[:-1] + bump)
    raised[1:] = np.maximum(raised[1:], moved[1:] + bump)
    return np.minimum(raised, MAX_SHRINK * (limits.upper - limits.lower))


def _position_excess(traj: Trajectory, limits: JointLimits) -> FloatArray:
    """How far each cubic piece passes the position limits between its ends [rad or m].

    Exact: each piece's extremes are at its ends or where its velocity vanishes inside it.
    A limit may be passed by the checker's slack (:data:`planners.checker.RELATIVE_SLACK`).

    Returns:
        Shape (K, 2, n): per piece, how far it goes below the lower limit (column 0) and
        above the upper one (column 1); 0 where it stays within.
    """
    c = traj.coefficients  # (K, 4, n): q0, qd0, qdd0 / 2, jerk / 6
    h = np.diff(traj.breakpoints)[:, None]
    a, b, lin = 3.0 * c[:, 3], 2.0 * c[:, 2], c[:, 1]  # velocity a t^2 + b t + lin
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(b * b - 4.0 * a * lin, 0.0))
        quadratic = np.abs(a) > 1e-300
        times = np.stack(
            [
                np.where(quadratic, (-b + root) / (2.0 * a), -lin / b),
                np.where(quadratic, (-b - root) / (2.0 * a), -lin / b),
            ]
        )
    inside = np.isfinite(times) & (times > 0.0) & (times < h) & (b * b >= 4.0 * a * lin)
    t = np.where(inside, times, 0.0)
    q = c[:, 0] + t * (c[:, 1] + t * (c[:, 2] + t * c[:, 3]))
    slack = RELATIVE_SLACK * np.maximum(np.abs(limits.lower), np.abs(limits.upper))
    below = np.where(inside, limits.lower - q, 0.0).max(axis=0)  # (K, n)
    above = np.where(inside, q - limits.upper, 0.0).max(axis=0)
    excess = np.stack([below, above], axis=1)
    return np.where(excess > slack, excess, 0.0)


def _dense_times(traj: Trajectory, per_interval: int) -> FloatArray:
    knots = traj.breakpoints
    fractions = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
    inner = knots[:-1, None] + fractions[None, :] * np.diff(knots)[:, None]
    return np.append(inner.reshape(-1), knots[-1])


def _integrable(
    w: FloatArray,
    layout: Layout,
    scale: tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray],
    kept: list[int],
) -> FloatArray:
    """The node states and jerks nearest those of ``w`` that meet the dynamics rows exactly.

    A guess sampled at the nodes breaks the triple-integrator rows wherever its jerk is not
    constant over an interval (a Ruckig move switches jerk between nodes; on long approaches
    the scaled defects reach 0.7), and IPOPT spends its first iterations repairing them. Per
    joint, with the interval lengths of ``w``, the node states are linear in the first state
    and the interval jerks; those are fitted by least squares to the sampled states, in the
    NLP's scaling, with the ``kept`` nodes (phase ends, the strike line) weighted
    :data:`KEPT_NODE_WEIGHT` and the jerks :data:`FIT_JERK_WEIGHT`. It leaves the median
    iteration count of cold strikes as it was and shortens the slowest solves (see
    :data:`KEPT_NODE_WEIGHT`).
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


def _trajectory(built: OptimalControlProblem, w: FloatArray) -> Trajectory:
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
    coefficients += _end_correction(
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


def _end_correction(
    knots: FloatArray, dq: FloatArray, dv: FloatArray, da: FloatArray
) -> FloatArray:
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


# ---------------------------------------------------------------------------- problem specs


def _zeros(n: int) -> FloatArray:
    return np.zeros(n)


def _quintic(
    q0: FloatArray,
    q1: FloatArray,
    duration: float,
    v1: FloatArray | None = None,
    a1: FloatArray | None = None,
) -> Trajectory:
    n = q0.size
    coefficients = quintic_coefficients(
        q0, q1, duration, 0.0, _zeros(n) if v1 is None else v1, 0.0, _zeros(n) if a1 is None else a1
    )
    return Trajectory([0.0, duration], coefficients[None])


def _guess_move(
    q0: FloatArray,
    v0: FloatArray,
    a0: FloatArray,
    q1: FloatArray,
    v1: FloatArray,
    a1: FloatArray,
    limits: JointLimits,
    duration: float | None = None,
) -> Trajectory:
    """Ruckig's time-optimal move (limits not enforced: it is only a guess)."""
    try:
        return state_to_state(
            q0, v0, a0, q1, v1, a1, limits, minimum_duration=duration, check_limits=False
        )
    except OptrajError:
        span = np.max(np.abs(q1 - q0) / limits.velocity)
        return _quintic(q0, q1, duration or max(2.0 * span, 0.2), v1, a1)


def _check_duration(
    what: str,
    name: str,
    duration: float,
    needed: FloatArray,
    limits: JointLimits,
    bound: Literal["velocity", "jerk"],
) -> None:
    """Raise when a fixed duration [s] is below a joint's lower bound ``needed`` [s], (n,).

    ``bound`` says which limits the bound counts: ``"velocity"`` (distance over the velocity
    limit) or ``"jerk"`` (the velocity, acceleration and jerk limits together).
    """
    joint = int(np.argmax(needed))
    if needed[joint] > duration * (1.0 + 1e-9):
        limits_text = (
            "velocity limit" if bound == "velocity" else "velocity, acceleration and jerk limits"
        )
        raise InfeasibleError(
            f"{what} needs at least {needed[joint]:.4g} s: joint {limits.names[joint]!r} "
            f"cannot move faster within its {limits_text}; {name} is {duration:.4g} s",
            limit="duration",
            joint=limits.names[joint],
            required=float(needed[joint]),
            allowed=duration,
        )


def _point_to_point(problem: PointToPoint) -> _Spec:
    limits = problem.limits
    n = limits.n
    a0 = _zeros(n) if problem.qdd_start is None else problem.qdd_start
    a1 = _zeros(n) if problem.qdd_goal is None else problem.qdd_goal
    guess = _guess_move(
        problem.q_start,
        problem.qd_start,
        a0,
        problem.q_goal,
        problem.qd_goal,
        a1,
        limits,
        problem.duration,
    )
    if problem.duration is not None and guess.duration > problem.duration * (1 + 1e-9):
        raise InfeasibleError(
            f"the move needs at least {guess.duration:.4g} s within the velocity, acceleration "
            f"and jerk limits; duration is {problem.duration:.4g} s",
            limit="duration",
            required=guess.duration,
            allowed=problem.duration,
        )
    guess = Trajectory(
        guess.breakpoints, guess.coefficients, phases=[Phase("move", 0.0, guess.duration)]
    )
    return _Spec(
        robot=problem.robot,
        limits=limits,
        names=("move",),
        durations=(problem.duration,),
        guess=guess,
        fixed=[
            _Fixed(0, "start", problem.q_start, problem.qd_start, a0),
            _Fixed(0, "end", problem.q_goal, problem.qd_goal, a1),
        ],
    )


def _waypoints(problem: Waypoints) -> _Spec:
    limits = problem.limits
    n = limits.n
    points = np.asarray(problem.waypoints)
    fixed_durations = problem.segment_durations
    tol = 0.0 if problem.via_tolerance is None else float(problem.via_tolerance)
    pieces = []
    names = []
    for k in range(len(points) - 1):
        duration = None if fixed_durations is None else float(fixed_durations[k])
        if duration is not None:  # inner waypoints: passed at any speed, within tol of them
            slack = tol * ((k > 0) + (k + 1 < len(points) - 1))
            spans = np.maximum(np.abs(points[k + 1] - points[k]) - slack, 0.0) / limits.velocity
            _check_duration(
                f"segment {k + 1}", f"segment_durations[{k}]", duration, spans, limits, "velocity"
            )
        pieces.append(
            (
                f"segment {k + 1}",
                [
                    _guess_move(
                        points[k],
                        _zeros(n),
                        _zeros(n),
                        points[k + 1],
                        _zeros(n),
                        _zeros(n),
                        limits,
                        duration,
                    )
                ],
            )
        )
        names.append(f"segment {k + 1}")
    guess = Trajectory.sequence(pieces, joint_names=limits.names)
    fixed = [_Fixed(0, "start", points[0], _zeros(n), _zeros(n))]
    fixed += [_Fixed(k, "end", points[k + 1], None, None, tol) for k in range(len(points) - 2)]
    fixed.append(_Fixed(len(points) - 2, "end", points[-1], _zeros(n), _zeros(n)))
    durations = tuple(
        None if fixed_durations is None else float(d)
        for d in (fixed_durations if fixed_durations is not None else [None] * len(names))
    )
    return _Spec(problem.robot, limits, tuple(names), durations, guess, fixed)


def _checked_warm_start(problem: Any, warm_start: Any) -> Trajectory | None:
    """``warm_start`` checked against the problem: None, or a Trajectory of its joints."""
    if warm_start is None:
        return None
    if not isinstance(warm_start, Trajectory):
        raise InvalidInputError(
            f"warm_start must be a planners.Trajectory or None, got {type(warm_start).__name__}",
            name="warm_start",
        )
    limits = getattr(problem, "limits", None)
    if isinstance(limits, JointLimits) and warm_start.dof != limits.n:
        raise InvalidInputError(
            f"warm_start moves {warm_start.dof} joints; the problem's robot has {limits.n}",
            name="warm_start",
        )
    return warm_start


def _cause(raised: OptrajError, failure: SolverError) -> BaseException | None:
    """The cause to chain ``raised`` to: the solver's own, or ``failure`` for a new kind."""
    return failure.__cause__ if isinstance(raised, SolverError) else failure


def _past_the_limits(window: WindowRatio | None) -> bool:
    """Whether a window check (None: none was made) found its window past the limits."""
    return window is not None and window.exceeds(1.0)


def _near_the_limit(
    failure: SolverError, problem: PoolStrike, choices: list[ContactChoice]
) -> SolverError:
    """The pool strike's last solver error, with a hint when the strike is near its limit.

    When the solver found the NLP (locally) infeasible (:data:`INFEASIBLE_STATUSES`) and
    every contact configuration of the contact search that was tried needs more than
    :data:`TIGHT_RATIO` of a velocity limit, the error also says so, with the fastest speed
    the best of them allows: close to that speed the line can need accelerations past their
    limits, which the contact choice does not check. The hint is not a bound: the speed it
    names is the velocity limits'. A contact kept from a warm start has room to spare by
    construction (:func:`planners.strike.contact.contact_near`) and is not counted. Otherwise the
    error is returned as it was.
    """
    if not choices or failure.status not in INFEASIBLE_STATUSES:
        return failure
    best = min(choices, key=lambda choice: choice.ratio)
    if best.ratio <= TIGHT_RATIO:
        return failure
    speed = float(problem.speed)
    tried, allows = (
        ("the contact configuration tried needs", "it allows")
        if len(choices) == 1
        else (f"the {len(choices)} contact configurations tried need", "the best allows")
    )
    hint = (
        f"at {speed:.3g} m/s {tried} at least {100.0 * best.ratio:.1f} % of a velocity limit "
        f"({best.binding_joint} binds; {allows} "
        f"up to {best.max_speed:.4g} m/s within the velocity limits); this close to that speed "
        f"the strike line can need more acceleration than the limits give: a slower strike "
        f"may plan"
    )
    return _detailed(failure, hint)


def _detailed(failure: SolverError, text: str) -> SolverError:
    """``failure`` with ``text`` added to its detail."""
    return SolverError(
        failure.solver,
        failure.status,
        iterations=failure.iterations,
        detail=f"{failure.detail}; {text}" if failure.detail else text,
    )


def _previous_contact(problem: PoolStrike, warm_start: Trajectory | None) -> FloatArray | None:
    """The contact configuration a previous pool solution recorded [rad], shape (n,).

    None when there is none, or it does not lie within this problem's position limits.
    """
    if warm_start is None:
        return None
    previous = warm_start.metadata.get("contact_configuration")
    if previous is None:
        return None
    try:  # an array, or a list once read back from JSON
        q = np.asarray(previous, dtype=float)
    except (TypeError, ValueError):
        return None
    if (
        q.shape != (problem.limits.n,)
        or not np.all(np.isfinite(q))
        or not problem.limits.contains(q)
    ):
        return None
    return q


def _contact_from(
    problem: PoolStrike, warm_start: Trajectory | None, margin: float
) -> ContactChoice | None:
    """The contact branch of a previous pool solution, if it still fits this problem.

    ``margin`` is the fraction of the velocity limits kept in reserve [-].
    """
    q = _previous_contact(problem, warm_start)
    return None if q is None else contact_near(problem, q, margin=margin)


def _lends_to(problem: PoolStrike, warm_start: Trajectory | None, choice: ContactChoice) -> bool:
    """Whether a warm start may seed the plan through ``choice``.

    Not when it is a pool solution through another IK branch (its contact configuration more
    than :data:`planners.strike.contact.BRANCH_SPREAD` from the choice's on some joint): IPOPT would
    have to drag the whole strike across from there, at the warm start's small barrier
    parameter, which took 300 to 630 iterations on strike benchmark shots whose ball moved 2
    cm (the search chose another branch once the kept one had no room left), against 30 to 70
    from the cold guess. A warm start that recorded no contact seeds any choice.
    """
    if warm_start is None:
        return False
    previous = warm_start.metadata.get("contact_configuration")
    if previous is None:
        return True
    q = _previous_contact(problem, warm_start)
    return q is not None and float(np.abs(q - choice.q).max()) <= BRANCH_SPREAD


def _pool(
    problem: PoolStrike, choice: ContactChoice, warm_start: Trajectory | None = None
) -> _Spec:
    """The pool strike's phases; the guess is a previous solution's, when one is given.

    A previous pool solution (a re-plan's warm start, with its primal and dual values) also
    gives the phase durations the grid starts from, which saves the IK of the strike line
    and the Ruckig moves of a fresh guess (about 8 ms).
    """
    limits = problem.limits
    n = limits.n
    phases = ("approach", "strike", "stop")
    if (
        warm_start is not None
        and isinstance(warm_start.metadata.get("warm_start"), WarmStart)
        and tuple(p.name for p in warm_start.phases) == phases
    ):
        guess = warm_start
    else:
        line = _window_guess(problem, choice)
        entry = line.sample(0.0)
        leave = line.sample(line.duration)
        approach = _guess_move(
            problem.q_start, _zeros(n), _zeros(n), entry.q, entry.qd, entry.qdd, limits
        )
        try:
            brake = stop(leave.q, leave.qd, leave.qdd, limits, check_limits=False)
        except OptrajError:
            brake = _quintic(leave.q, leave.q + 0.1 * leave.qd, 0.2)  # pragma: no cover
        guess = Trajectory.sequence(
            [("approach", [approach]), ("strike", [line]), ("stop", [brake])],
            joint_names=limits.names,
        )
    direction = np.asarray(problem.direction)
    e1, e2 = normal_pair(direction)
    return _Spec(
        robot=problem.robot,
        limits=limits,
        names=phases,
        durations=(None, problem.window, None),
        guess=guess,
        fixed=[
            _Fixed(0, "start", np.asarray(problem.q_start), _zeros(n), _zeros(n)),
            _Fixed(2, "end", None, _zeros(n), _zeros(n)),
        ],
        params={
            "entry": problem.entry_point,
            "direction": direction,
            "e1": e1,
            "e2": e2,
            "speed": float(problem.speed),
        },
        strike_phase=1,
        contact=choice,
    )


def _window_guess(problem: PoolStrike, choice: ContactChoice) -> Trajectory:
    """The strike window of a pool strike's first guess, ``problem.window`` long.

    The line followed by IK with the cue's roll kept from the contact configuration
    (:func:`planners.strike.time_optimal_strike.strike_line`, :data:`LINE_SAMPLES` samples, then
    :data:`LINE_SAMPLES_FINE` when the joints jump between them: a joint pinned on a
    position limit makes the others turn fast). When the finer line still jumps, or a pose on
    it has no solution with that roll, the guess joins the contact choice's own entry,
    contact and exit configurations (which it reached with the roll free) by quintics at the
    contact's joint velocity; the solver then puts the cue on the line.
    """
    failure: OptrajError | None = None
    for samples in (LINE_SAMPLES, LINE_SAMPLES_FINE):
        try:
            return strike_line(problem, samples, q_contact=choice.q)
        except (PathJumpError, UnreachableError) as error:
            failure = error
            if isinstance(error, UnreachableError):
                break  # more samples reach no more poses
    if choice.q_entry is None or choice.q_exit is None:
        raise failure  # pragma: no cover - a pool choice always has its entry and exit
    q = np.asarray(choice.q, dtype=float)
    qd = np.asarray(choice.qd, dtype=float)
    into = float(problem.contact_delay)
    out = float(problem.window) - into
    coefficients = np.stack(
        [
            quintic_coefficients(choice.q_entry, q, into, qd, qd),
            quintic_coefficients(q, choice.q_exit, out, qd, qd),
        ]
    )
    return Trajectory([0.0, into, into + out], coefficients)


def _paddle(problem: PaddleStrike, choice: ContactChoice) -> _Spec:
    limits = problem.limits
    n = limits.n
    q_contact = np.asarray(problem.q_contact)
    contact_time = float(problem.contact_time)
    start = _Fixed(0, "start", np.asarray(problem.q_start), _zeros(n), _zeros(n))
    # No joint is faster than its distance over its velocity limit; arriving at rest, none is
    # faster than alone (planners.lower_bound), within Ruckig's range.
    needed = np.abs(q_contact - np.asarray(problem.q_start)) / limits.velocity
    bound: Literal["velocity", "jerk"] = "velocity"
    if float(problem.speed) == 0.0:
        try:
            needed = joint_min_durations(q_start=problem.q_start, q_goal=q_contact, limits=limits)
            bound = "jerk"
        except SolverError:
            pass
    _check_duration("the paddle", "contact_time", contact_time, needed, limits, bound)
    if float(problem.speed) == 0.0:
        approach = _quintic(np.asarray(problem.q_start), q_contact, contact_time)
        guess = Trajectory.sequence([("approach", [approach])], joint_names=limits.names)
        return _Spec(
            robot=problem.robot,
            limits=limits,
            names=("approach",),
            durations=(contact_time,),
            guess=guess,
            fixed=[start, _Fixed(0, "end", q_contact, _zeros(n), _zeros(n))],
        )
    qd_contact = choice.qd
    approach = _quintic(np.asarray(problem.q_start), q_contact, contact_time, qd_contact)
    try:
        brake = stop(q_contact, qd_contact, _zeros(n), limits, check_limits=False)
    except OptrajError:  # pragma: no cover - a guess only
        brake = _quintic(q_contact, q_contact, 0.5)
    guess = Trajectory.sequence(
        [("approach", [approach]), ("stop", [brake])], joint_names=limits.names
    )
    return _Spec(
        robot=problem.robot,
        limits=limits,
        names=("approach", "stop"),
        durations=(contact_time, None),
        guess=guess,
        fixed=[
            start,
            _Fixed(0, "end", q_contact, None, None),
            _Fixed(1, "end", None, _zeros(n), _zeros(n)),
        ],
        params={
            "contact_velocity": float(problem.speed) * problem.normal,
            "offset": BALL_OFFSET,
        },
        contact_phase=0,
        contact=choice,
    )
