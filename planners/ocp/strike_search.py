"""The search over a strike's contact configurations and the error it raises when all fail."""

from __future__ import annotations

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
)
from optraj.planners.ocp.formulation import (
    pool_spec,
)
from optraj.planners.ocp.options import (
    BUDGET_SPENT,
    INFEASIBLE_STATUSES,
)
from optraj.planners.strike.contact import (
    ContactChoice,
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
    of the line, and its window can need more than the limits at a ratio of 0.75 (strike
    benchmark ball 15 at 1.2 m/s, second choice: 1.05). None too when the check has no
    answer (no IK start on the line, no finite point).
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
        traj = planner._plan(problem, pool_spec(problem, choice, warm_start), warm_start)
    except SolverError as error:
        if error.status == BUDGET_SPENT:
            raise
        return error
    traj.metadata["contact_attempts"] = attempt
    traj.metadata["contact_from_warm_start"] = from_warm_start
    return stamp(traj, planner.name, started, contact_time=searching)
