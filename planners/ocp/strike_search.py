"""The search over a strike's contact configurations and the error it raises when all fail."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    WINDOW_CHECK,
    InfeasibleError,
    OptrajError,
    SolverError,
)
from optraj.planners.base import stamp
from optraj.planners.ocp.failures import (
    detailed_failure,
    near_the_limit,
    past_the_limits,
    solver_cause,
)
from optraj.planners.ocp.formulation import (
    contact_from,
    lends_to,
    pool_spec,
)
from optraj.planners.ocp.options import (
    BUDGET_SPENT,
    INFEASIBLE_STATUSES,
)
from optraj.planners.strike.contact import (
    ContactChoice,
    contact_choices,
)
from optraj.planners.strike.window_check import WindowRatio
from optraj.planners.trajectory import Trajectory
from optraj.problems import PoolStrike

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]


def window_ratio(
    planner: OptimalControl, problem: PoolStrike, choice: ContactChoice, failure: SolverError | None
) -> WindowRatio | None:
    """The window check of a choice once a solve was found infeasible, else None.

    Whatever the choice's velocity ratio: the contact choice checks three configurations
    of the line only, and a window can need more than the limits at a ratio well below 1.
    None too when the check has no answer (no IK start on the line, no finite point).
    """
    if failure is None or failure.status not in INFEASIBLE_STATUSES:
        return None
    planner._in_budget(failure, "the window check")
    try:
        return planner._window_check(problem, choice.q)
    except OptrajError:
        return None


def alone_error(
    planner: OptimalControl,
    failure: SolverError,
    problem: PoolStrike,
    choice: ContactChoice,
    *,
    searched: bool,
) -> SolverError:
    """The error of a pool strike solved from one contact only (``contact_retries=0``).

    A window past the limits says nothing of other contacts, so the solver's error stays,
    with the window check's finding added; a searched ``choice`` also gets
    :func:`near_the_limit`'s hint (a warm start's contact has room by construction).
    """
    raised = near_the_limit(failure, problem, [choice]) if searched else failure
    window = planner._window(problem, choice, failure)
    if window is None or not past_the_limits(window):
        return raised
    return detailed_failure(
        raised,
        f"from this contact configuration {window.describe()}; other contact "
        f"configurations (contact_retries > 0) may plan",
    )


def strike_error(
    planner: OptimalControl,
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
        f"limits ({planner.solver} status {failure.status!r}); {best.describe()}: {remedy} "
        f"may plan",
        limit=best.limit,
        joint=best.joint,
        required=best.required,
        allowed=best.allowed,
        max_speed=best.max_speed,
        found_by=WINDOW_CHECK,
    )


def attempt(
    planner: OptimalControl,
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
        spec = pool_spec(problem, choice, warm_start, planner.clearance)
        traj = planner._plan(problem, spec, warm_start)
    except SolverError as error:
        if error.status == BUDGET_SPENT:
            raise
        return error
    traj.metadata["contact_attempts"] = attempt
    traj.metadata["contact_from_warm_start"] = from_warm_start
    return stamp(traj, planner.name, started, contact_time=searching)


@dataclass
class StrikeSearch:
    """A pool strike's contact configurations tried so far and what their solves found.

    Attributes:
        started: When the plan started (``time.perf_counter()``) [s].
        searching: Wall time of the contact choices so far [s].
        tried: The configurations solved from (or skipped), to exclude from new searches.
        found: The searches' choices tried, for the error's hint.
        windows: Their window checks, once a solve was found infeasible (else None).
        failure: The last solver failure, or None.
    """

    started: float
    searching: float = 0.0
    tried: list[FloatArray] = field(default_factory=list)
    found: list[ContactChoice] = field(default_factory=list)
    windows: list[WindowRatio | None] = field(default_factory=list)
    failure: SolverError | None = None


def plan_pool_strike(
    planner: OptimalControl, problem: PoolStrike, warm_start: Trajectory | None, started: float
) -> Trajectory:
    """Plan a pool strike, trying further contact configurations while solves fail.

    A warm start's contact branch first (when it still has room, one local IK instead of
    the search), then the contact search's choices, once as set and once more over twice as
    many candidates for branches the first missed (``contact_retries`` of them each time).
    After an infeasible solve, a choice is solved from only if its window can keep within
    the limits.

    Raises:
        InfeasibleError: No contact configuration can make the strike.
        SolverError: Every solve failed (the last failure, with the search's hint).
    """
    planner._strike_start_held(problem)
    search = StrikeSearch(started)
    if planner.reuse_contact:
        seeded = contact_from(problem, warm_start, planner.margin)
        search.searching = time.perf_counter() - started
        if seeded is not None:
            outcome = _seeded_attempt(planner, problem, seeded, warm_start, search)
            if outcome is not None:
                return outcome
            warm_start = None  # its branch failed: the search's choices start cold
    if planner.contact_retries == 0:
        return planner._plan_alone(problem, warm_start, started, search.searching)
    for candidates in (planner.contact_candidates, 2 * planner.contact_candidates):
        choices = _searched_choices(planner, problem, candidates, search)
        if choices is None:
            break  # the wider search refused what the first accepted: report the solver
        for choice in choices:
            outcome = _choice_attempt(planner, problem, choice, warm_start, search)
            if outcome is not None:
                return outcome
    if search.failure is None:  # pragma: no cover - the first search returns a branch
        raise SolverError(planner.solver, "no contact configuration to solve from")
    raised = planner._strike_error(search.failure, problem, search.found, search.windows)
    raise raised from solver_cause(raised, search.failure)


def _seeded_attempt(
    planner: OptimalControl,
    problem: PoolStrike,
    seeded: ContactChoice,
    warm_start: Trajectory | None,
    search: StrikeSearch,
) -> Trajectory | None:
    """Plan from a warm start's contact branch; None when that failed (in ``search``).

    Raises:
        SolverError: It failed and ``contact_retries=0`` allows no other configuration.
    """
    search.tried.append(seeded.q)
    outcome = planner._attempt(
        problem, seeded, warm_start, len(search.tried), search.started, search.searching, True
    )
    if isinstance(outcome, Trajectory):
        return outcome
    if planner.contact_retries == 0:  # the one configuration allowed
        raised = planner._alone_error(outcome, problem, seeded, searched=False)
        raise raised from solver_cause(raised, outcome)
    search.failure = outcome
    return None


def _searched_choices(
    planner: OptimalControl, problem: PoolStrike, candidates: int, search: StrikeSearch
) -> tuple[ContactChoice, ...] | None:
    """The contact search's new branches over ``candidates`` configurations.

    None when it refuses the strike after a solve failed (the solver's failure is then the
    better report).

    Raises:
        InfeasibleError: It refuses the strike before any solve.
        SolverError: The plan's time budget is spent.
    """
    planner._in_budget(search.failure, "the contact search")
    searched = time.perf_counter()
    try:
        return contact_choices(
            problem,
            1 + planner.contact_retries,
            candidates=candidates,
            exclude=search.tried,
            margin=planner.margin,
        )
    except InfeasibleError:
        if search.failure is None:
            raise
        return None
    finally:
        search.searching += time.perf_counter() - searched


def _choice_attempt(
    planner: OptimalControl,
    problem: PoolStrike,
    choice: ContactChoice,
    warm_start: Trajectory | None,
    search: StrikeSearch,
) -> Trajectory | None:
    """Plan from a searched choice; None when it failed or its window was past the limits.

    The warm start seeds the first choice only, and only when it lends to its branch
    (:func:`planners.ocp.formulation.lends_to`).
    """
    search.tried.append(choice.q)
    search.found.append(choice)
    window = planner._window(problem, choice, search.failure)
    search.windows.append(window)
    if past_the_limits(window):
        return None
    lend = len(search.tried) == 1 and lends_to(problem, warm_start, choice)
    outcome = planner._attempt(
        problem,
        choice,
        warm_start if lend else None,
        len(search.tried),
        search.started,
        search.searching,
        False,
    )
    if isinstance(outcome, Trajectory):
        return outcome
    search.failure = outcome
    if search.windows[-1] is None:
        search.windows[-1] = planner._window(problem, choice, outcome)
    return None
