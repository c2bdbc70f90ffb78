"""The columns of a sweep's rows: one table of names, units and meanings.

Every row that :func:`optraj.sweeps.run` returns or writes is a flat dict with exactly the
keys of :data:`COLUMNS`, in that order; a value that does not apply is None. The columns of
the MuJoCo outcome (:data:`OUTCOME_COLUMNS`) are filled only by a job that tracks its plans
(``ShotJob(outcome=True)``).
"""

from __future__ import annotations

__all__ = ["COLUMNS", "OUTCOME_COLUMNS", "STATUSES", "empty_row"]

#: The MuJoCo outcome's columns (:mod:`optraj.sweeps.outcome_row`): name -> (unit, meaning).
OUTCOME_COLUMNS: dict[str, tuple[str, str]] = {
    "hit": ("", "whether the tracked tool touched the ball; None when not run"),
    "heading_error": (
        "deg",
        "launch heading minus the commanded one (pool: signed, in the table plane; paddle: "
        "unsigned, 3-D); inf when missed, None when not run",
    ),
    "speed_error": (
        "-",
        "launch speed over the calibrated ideal, minus 1; inf when missed, None when not run",
    ),
    "on_target": (
        "",
        "hit, heading within 0.5 deg and speed within 2 % of the ideal; None when not run",
    ),
    "outcome_time": ("s", "wall time of tracking and judging the plan; None when not run"),
    "outcome_error": (
        "",
        "'Type: message' of an exception raised while tracking or judging the plan (the row "
        "stays planned, the outcome columns None); None otherwise",
    ),
}

#: name -> (unit, meaning); the unit is "" for a name, a flag or a count, "-" for a ratio.
COLUMNS: dict[str, tuple[str, str]] = {
    "shot_id": ("", "stable id of the shot, made from its inputs"),
    "robot": ("", "the robot's name"),
    "kind": ("", "the registry kind of the shot's problem: pool-shot or paddle-strike"),
    "ball_x": ("m", "ball centre x, robot base frame"),
    "ball_y": ("m", "ball centre y, robot base frame"),
    "ball_z": ("m", "ball centre z, robot base frame"),
    "heading": (
        "deg",
        "shot direction from +x about +z: the cue's direction (pool), the paddle normal at "
        "contact (paddle)",
    ),
    "speed": (
        "m/s",
        "commanded strike speed: the cue tip's (pool), the paddle's along its normal (paddle)",
    ),
    "planner": ("", "the planner's registry name"),
    "status": ("", "planned, refused, failed or timed out (see STATUSES)"),
    "error_type": ("", "class name of the exception raised, None when planned"),
    "error_message": ("", "the exception's message, None when planned"),
    "binding_joint": (
        "",
        "the joint that binds max_speed: the one a refusal's InfeasibleError names, else the "
        "contact choice's (the first joint to reach its velocity limit as the speed rises); "
        "None when neither gives one",
    ),
    "binding_quantity": (
        "",
        "the limit that binds: the one a refusal's InfeasibleError names (velocity, "
        "position, ...), else velocity when the contact choice gives max_speed",
    ),
    "max_speed": (
        "m/s",
        "fastest strike speed the limits allow: the one a refusal's InfeasibleError gives, "
        "else the velocity limits' at the contact configuration "
        "planners.strike.contact.choose_contact chooses (its defaults); None when neither "
        "gives one (the contact search failed, or the refusal names none)",
    ),
    "contact_search_time": (
        "s",
        "wall time of the contact search (choose_contact); None when it was not reached",
    ),
    "motion_time": ("s", "duration of the planned motion"),
    "iterations": ("", "solver iterations of the plan (SolveStats.iterations)"),
    "plan_time": (
        "s",
        "wall time of the shot from building the problem to checking the plan, the contact "
        "search included, the outcome not",
    ),
    "check_ok": ("", "whether planners.check found the plan within every limit"),
    **OUTCOME_COLUMNS,
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
