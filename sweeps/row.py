"""One shot's row: plan the shot and record what happened.

The row has the columns of :data:`optraj.sweeps.columns.COLUMNS`.

:func:`plan_row` never raises for the shot's sake: an exception becomes a row with its type
and message. Before planning, it searches the shot's contact once
(:func:`optraj.planners.strike.contact.choose_contact`, its defaults: 16 candidates, seed 0,
no margin) for the fastest strike speed the velocity limits allow there and its binding
joint (:func:`contact_columns`); a search that fails leaves those columns None and the rest of
the row as the planner makes it. ``choose_contact`` remembers its answer per problem, so a
planner that chooses its contact with the same defaults (``contact="choose"``) reuses this
search; one that plans at the problem's own contact pays for it on top.
"""

from __future__ import annotations

import time

from optraj import planners
from optraj.errors import InfeasibleError, JointLimitError, UnreachableError, WorkspaceError
from optraj.planners.base import Planner
from optraj.planners.strike.contact import choose_contact
from optraj.problems import PaddleStrike, PoolStrike
from optraj.sweeps.columns import empty_row
from optraj.sweeps.outcome_row import outcome_columns
from optraj.sweeps.shots import Shot
from optraj.sweeps.time_limit import ShotTimeout, time_limit

__all__ = ["REFUSALS", "contact_columns", "error_row", "inputs_row", "plan_row"]

#: The errors that mean "this shot cannot be made" (status ``refused``); any other
#: exception is a failure (status ``failed``).
REFUSALS = (InfeasibleError, UnreachableError, WorkspaceError, JointLimitError)


def inputs_row(shot: Shot, planner: str) -> dict[str, object]:
    """A row with the shot's inputs filled in and every outcome column None."""
    row = empty_row()
    row.update(
        shot_id=shot.shot_id,
        robot=shot.robot,
        kind=shot.kind,
        ball_x=shot.ball[0],
        ball_y=shot.ball[1],
        ball_z=shot.ball[2],
        heading=shot.heading,
        speed=shot.speed,
        planner=planner,
    )
    return row


def error_row(
    shot: Shot, planner: str, status: str, error_type: str, message: str
) -> dict[str, object]:
    """The row of a shot that produced no plan."""
    row = inputs_row(shot, planner)
    row.update(status=status, error_type=error_type, error_message=message)
    return row


def contact_columns(problem: PoolStrike | PaddleStrike) -> dict[str, object]:
    """The contact choice's columns of a strike: ``max_speed`` [m/s] and its binding limit.

    One :func:`optraj.planners.strike.contact.choose_contact` with its defaults. Never raises
    for the shot's sake: when the search fails (the strike is out of reach, over the limits
    at every contact, ...), ``max_speed``, ``binding_joint`` and ``binding_quantity`` are None.

    Returns:
        ``max_speed`` (:attr:`ContactChoice.max_speed`, inf when no joint has to move),
        ``binding_joint`` (None when no joint binds), ``binding_quantity`` (``"velocity"``)
        and ``contact_search_time`` [s].
    """
    start = time.perf_counter()
    columns: dict[str, object] = dict.fromkeys(("max_speed", "binding_joint", "binding_quantity"))
    try:
        choice = choose_contact(problem)
    except ShotTimeout:
        raise
    except Exception:  # the planner will meet (and the row record) whatever stopped it
        pass
    else:
        columns.update(
            max_speed=float(choice.max_speed),
            binding_joint=choice.binding_joint or None,
            binding_quantity="velocity",
        )
    columns["contact_search_time"] = time.perf_counter() - start
    return columns


def plan_row(
    planner: Planner,
    name: str,
    shot: Shot,
    seconds: float | None = None,
    outcome: bool = False,
) -> dict[str, object]:
    """Plan ``shot`` with ``planner`` (registry name ``name``) within ``seconds``; its row.

    Args:
        planner: The planner.
        name: Its registry name (the ``planner`` column).
        shot: The shot.
        seconds: Longest the shot may take [s], the outcome included; no limit when None.
        outcome: Track a planned shot in MuJoCo and fill the outcome columns
            (:func:`optraj.sweeps.outcome_row.outcome_columns`).
    """
    start = time.perf_counter()
    contact: dict[str, object] = {}
    try:
        with time_limit(seconds):
            problem = shot.problem()
            contact = contact_columns(problem)
            trajectory = planner.plan(problem)
            verdict = planners.check(trajectory, problem).ok
    except ShotTimeout as exc:
        row = error_row(shot, name, "timed out", "ShotTimeout", str(exc))
        row.update(contact)
    except Exception as exc:  # every failure is a row, never a lost shot
        row = _refusal_row(shot, name, exc, contact)
    else:
        row = inputs_row(shot, name)
        row.update(
            contact,
            status="planned",
            motion_time=float(trajectory.duration),
            iterations=planners.SolveStats.of(trajectory).iterations,
            check_ok=bool(verdict),
        )
    row["plan_time"] = time.perf_counter() - start
    if outcome and row["status"] == "planned":
        row.update(_outcome(trajectory, problem, seconds, time.perf_counter() - start))
    return row


def _outcome(
    trajectory: planners.Trajectory,
    problem: PoolStrike | PaddleStrike,
    seconds: float | None,
    spent: float,
) -> dict[str, object]:
    """The outcome columns within what is left of the shot's time limit ``seconds`` [s]."""
    limit = "" if seconds is None else f" of {seconds:.6g} s"
    stopped = f"ShotTimeout: the shot ran past the time limit{limit}"
    if seconds is not None and spent >= seconds:
        return {"outcome_time": 0.0, "outcome_error": stopped + " before its outcome"}
    try:
        with time_limit(None if seconds is None else seconds - spent):
            columns = outcome_columns(trajectory, problem)
    except ShotTimeout:  # raised between the outcome's own handler and its return
        return {"outcome_error": stopped + " during its outcome"}
    if str(columns["outcome_error"]).startswith("ShotTimeout"):
        columns["outcome_error"] = stopped + " during its outcome"
    return columns


def _refusal_row(
    shot: Shot, name: str, exc: Exception, contact: dict[str, object]
) -> dict[str, object]:
    status = "refused" if isinstance(exc, REFUSALS) else "failed"
    row = error_row(shot, name, status, type(exc).__name__, str(exc))
    row.update(contact)
    if isinstance(exc, InfeasibleError):  # the refusal's own finding, not the contact's
        fastest = None if exc.max_speed is None else float(exc.max_speed)
        row.update(binding_joint=exc.joint, binding_quantity=exc.limit, max_speed=fastest)
    return row
