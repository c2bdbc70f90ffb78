"""The errors a failed strike plan raises, with their causes and the limits they press."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    OptrajError,
    SolverError,
)
from optraj.planners.ocp.options import (
    INFEASIBLE_STATUSES,
    TIGHT_RATIO,
)
from optraj.planners.strike.contact import (
    ContactChoice,
)
from optraj.planners.strike.window_check import WindowRatio
from optraj.problems import PoolStrike

FloatArray = NDArray[np.float64]


def solver_cause(raised: OptrajError, failure: SolverError) -> BaseException | None:
    """The cause to chain ``raised`` to: the solver's own, or ``failure`` for a new kind."""
    return failure.__cause__ if isinstance(raised, SolverError) else failure


def past_the_limits(window: WindowRatio | None) -> bool:
    """Whether a window check (None: none was made) found its window past the limits."""
    return window is not None and window.exceeds(1.0)


def near_the_limit(
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
    return detailed_failure(failure, hint)


def detailed_failure(failure: SolverError, text: str) -> SolverError:
    """``failure`` with ``text`` added to its detail."""
    return SolverError(
        failure.solver,
        failure.status,
        iterations=failure.iterations,
        detail=f"{failure.detail}; {text}" if failure.detail else text,
    )
