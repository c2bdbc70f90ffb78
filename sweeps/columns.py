"""The columns of a sweep's rows: one table of names, units and meanings.

Every row that :func:`optraj.sweeps.run` returns or writes is a flat dict with exactly the
keys of :data:`COLUMNS`, in that order; a value that does not apply is None.
"""

from __future__ import annotations

__all__ = ["COLUMNS", "STATUSES", "empty_row"]

#: name -> (unit, meaning); the unit is "" for a name, a flag or a count.
COLUMNS: dict[str, tuple[str, str]] = {
    "shot_id": ("", "stable id of the shot, made from its inputs"),
    "robot": ("", "the robot's name"),
    "ball_x": ("m", "ball centre x, robot base frame"),
    "ball_y": ("m", "ball centre y, robot base frame"),
    "ball_z": ("m", "ball centre z, robot base frame"),
    "heading": ("deg", "shot direction from +x about +z"),
    "speed": ("m/s", "commanded cue speed at the strike"),
    "planner": ("", "the planner's registry name"),
    "status": ("", "planned, refused, failed or timed out (see STATUSES)"),
    "error_type": ("", "class name of the exception raised, None when planned"),
    "error_message": ("", "the exception's message, None when planned"),
    "binding_joint": ("", "the joint an InfeasibleError names as binding"),
    "binding_quantity": ("", "the limit an InfeasibleError names (velocity, position, ...)"),
    "max_speed": ("m/s", "fastest strike speed the limits allow, when a refusal gives it"),
    "motion_time": ("s", "duration of the planned motion"),
    "iterations": ("", "solver iterations of the plan (SolveStats.iterations)"),
    "plan_time": ("s", "wall time of building the problem and planning it"),
    "check_ok": ("", "whether planners.check found the plan within every limit"),
}

#: status -> meaning.
STATUSES: dict[str, str] = {
    "planned": "the planner returned a trajectory",
    "refused": "the shot cannot be made: out of reach or over a limit (InfeasibleError, "
    "UnreachableError, WorkspaceError, JointLimitError)",
    "failed": "any other exception, or the worker process died during the shot",
    "timed out": "the shot ran past the sweep's time limit and was stopped",
}


def empty_row() -> dict[str, object]:
    """A row with every column set to None."""
    return dict.fromkeys(COLUMNS)
