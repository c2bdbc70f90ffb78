"""One shot's row: plan the shot and record what happened.

The row has the columns of :data:`optraj.sweeps.columns.COLUMNS`.

:func:`plan_row` never raises for the shot's sake: an exception becomes a row with its type
and message.
"""

from __future__ import annotations

import time

from optraj import planners
from optraj.errors import InfeasibleError, JointLimitError, UnreachableError, WorkspaceError
from optraj.planners.base import Planner
from optraj.sweeps.columns import empty_row
from optraj.sweeps.shots import Shot
from optraj.sweeps.time_limit import ShotTimeout, time_limit

__all__ = ["REFUSALS", "error_row", "inputs_row", "plan_row"]

#: The errors that mean "this shot cannot be made" (status ``refused``); any other
#: exception is a failure (status ``failed``).
REFUSALS = (InfeasibleError, UnreachableError, WorkspaceError, JointLimitError)


def inputs_row(shot: Shot, planner: str) -> dict[str, object]:
    """A row with the shot's inputs filled in and every outcome column None."""
    row = empty_row()
    row.update(
        shot_id=shot.shot_id,
        robot=shot.robot,
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


def plan_row(
    planner: Planner, name: str, shot: Shot, seconds: float | None = None
) -> dict[str, object]:
    """Plan ``shot`` with ``planner`` (registry name ``name``) within ``seconds``; its row."""
    start = time.perf_counter()
    try:
        with time_limit(seconds):
            problem = shot.problem()
            trajectory = planner.plan(problem)
            verdict = planners.check(trajectory, problem).ok
    except ShotTimeout as exc:
        row = error_row(shot, name, "timed out", "ShotTimeout", str(exc))
    except Exception as exc:  # every failure is a row, never a lost shot
        row = _refusal_row(shot, name, exc)
    else:
        row = inputs_row(shot, name)
        row.update(
            status="planned",
            motion_time=float(trajectory.duration),
            iterations=planners.SolveStats.of(trajectory).iterations,
            check_ok=bool(verdict),
        )
    row["plan_time"] = time.perf_counter() - start
    return row


def _refusal_row(shot: Shot, name: str, exc: Exception) -> dict[str, object]:
    status = "refused" if isinstance(exc, REFUSALS) else "failed"
    row = error_row(shot, name, status, type(exc).__name__, str(exc))
    if isinstance(exc, InfeasibleError):
        fastest = None if exc.max_speed is None else float(exc.max_speed)
        row.update(binding_joint=exc.joint, binding_quantity=exc.limit, max_speed=fastest)
    return row
