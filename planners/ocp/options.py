"""Settings of :class:`planners.ocp.optimal_control.OptimalControl`: defaults, caps and checks."""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InvalidInputError,
    MissingDependencyError,
)
from optraj.planners.strike.contact import (
    HEADROOM,
)
from optraj.validation import (
    MAX_DURATION,
    as_choice,
    as_count,
    as_number,
    as_positive,
)

FloatArray = NDArray[np.float64]


#: Objective terms that can be weighted.
OBJECTIVES = ("time", "jerk", "effort")
#: CasADi NLP plugins that can be named (the installed CasADi decides which load). Left
#: out: fatrop (the transcription is not in its stage-wise layout) and blocksqp (it needs
#: HSL's MA27, which CasADi's wheels do not ship). sqpmethod (qpOASES) suits small problems
#: only.
SOLVERS = ("ipopt", "sqpmethod", "bonmin", "knitro", "snopt", "worhp")
#: Torques above this fraction of their limit get rows at the surrounding nodes [-].
TORQUE_WATCH = 0.9
#: Points per interval at which the torques are evaluated after a solve.
TORQUE_POINTS = 4
#: Rounds of solve, verify, refine (linear torque rows converge in a few warm rounds).
ROUNDS = 8
#: Weight of the term that keeps neighbouring intervals of a free phase alike [-]: small, so
#: that the nodes of a minimum-time joint move can sit on its jerk switches.
GRID_WEIGHT = 1e-2
#: The same weight in a pool strike: larger, for faster solves at the cost of slightly
#: longer motions (a uniform grid, ``free_grid=False``, is faster and longer still).
STRIKE_GRID_WEIGHT = 1.0
#: Weight of the term that keeps each interval of a free move near its length in the first
#: point, when that point's nodes sit on the jerk switches of the joint that needs longest
#: alone (:func:`planners.ocp.guesses.switch_times`); it replaces :data:`GRID_WEIGHT` there.
ANCHOR_WEIGHT = 1e-2
#: IPOPT's first barrier parameter in a cold solve from such a first point [-]: that point
#: is close to the solution, which IPOPT's own start (0.1) would push far into the interior
#: before the barrier comes down again.
CLOSE_MU_INIT = 1e-6
#: The same in a cold solve of a pool strike [-]: its first point (the strike line by IK, the
#: approach and stop by Ruckig) is nearer the solution than IPOPT's own start assumes, though
#: less so than a move's on its jerk switches.
STRIKE_MU_INIT = 1e-4
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
#: ends and on the strike line when it is fitted to the dynamics rows (:func:`integrable`).
#: A much heavier weight over-constrains short phases, whose both ends it holds.
KEPT_NODE_WEIGHT = 30.0
#: Weight of the (scaled) jerks in that fit: small, it only settles what the states leave free.
FIT_JERK_WEIGHT = 1e-3
#: Strike-phase node velocities stay within this multiple of the contact choice's ratio (the
#: largest fraction of a velocity limit the line needs) [-]; see :func:`strike_caps`.
STRIKE_VELOCITY_ROOM = 3.0
#: Strike-phase node accelerations stay within this multiple of the ratio squared (the
#: accelerations the line needs grow with the square of its speed) [-]. Without these bounds
#: slow strikes spend their long window on self-motion that carries the cue off its line
#: between nodes; at the usual speeds both bounds lie past the limits.
STRIKE_ACCELERATION_ROOM = 10.0
#: A pool strike whose contact configurations all need more than this fraction of a velocity
#: limit is near the fastest speed they allow: once the NLP is found infeasible, the error says
#: so [-]. The contact choice's own threshold for room to spare.
TIGHT_RATIO = HEADROOM
#: The solver statuses of an NLP found (locally) infeasible.
INFEASIBLE_STATUSES = frozenset({"Infeasible_Problem_Detected", "Restoration_Failed"})
#: Default wall-time budget of one plan [s] (``OptimalControl(time_budget=...)``): well past
#: the slowest feasible plans; beyond it a solve is lost in a problem it will not settle.
TIME_BUDGET = 60.0
#: :attr:`optraj.errors.SolverError.status` of a plan stopped because its time budget is spent.
BUDGET_SPENT = "time budget spent"
#: IK samples of the strike line in a pool strike's first guess (:func:`window_guess`).
LINE_SAMPLES = 10
#: The same when the joints jump between those samples by more than
#: :func:`planners.profiles.cartesian.follow_tool_path`'s threshold.
LINE_SAMPLES_FINE = 40


def objective_weights(objective: str | Mapping[str, float]) -> dict[str, float]:
    """The validated objective weights of ``objective`` (a term name or a mapping of weights)."""
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


def solver_name(solver: str) -> str:
    """``solver`` checked as a known NLP solver whose CasADi plugin is installed."""
    as_choice(solver, "solver", SOLVERS)
    if not ca.has_nlpsol(solver):
        raise MissingDependencyError(
            package=f"casadi with the {solver} plugin",
            extra="all",
            feature=f"OptimalControl(solver={solver!r})",
        )
    return solver


def checked_solver_options(solver_options: Mapping[str, Any] | None) -> dict[str, Any]:
    """A copy of ``solver_options`` (None for none), checked to be a mapping."""
    if solver_options is not None and not isinstance(solver_options, Mapping):
        raise InvalidInputError(
            f"solver_options must be a mapping of option names to values, got {solver_options!r}",
            name="solver_options",
        )
    return dict(solver_options or {})


def checked_intervals(
    intervals: int | Mapping[str, int] | None,
) -> int | dict[str, int] | None:
    """``intervals`` checked: a count for every phase, counts by phase name, or None."""
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
    return intervals


def checked_max_interval(max_interval: float) -> float:
    """``max_interval`` [s] checked to be longer than :data:`MIN_INTERVAL`."""
    value = as_positive(max_interval, "max_interval", "s", maximum=MAX_DURATION)
    if value <= MIN_INTERVAL:
        raise InvalidInputError(
            f"max_interval must be > {MIN_INTERVAL:g} s (the shortest interval), got {value:.6g} s",
            name="max_interval",
        )
    return value


def checked_fraction(name: str, value: float) -> float:
    """A margin ``value`` [-] checked to lie in [0, 0.5)."""
    fraction = as_number(value, name, minimum=0.0, maximum=0.5)
    if fraction == 0.5:
        raise InvalidInputError(f"{name} must be < 0.5, got {value!r}", name=name)
    return fraction


def checked_torque(torque: bool | str) -> bool | str:
    """``torque`` checked to be ``"auto"``, True or False."""
    if not (isinstance(torque, bool) or (isinstance(torque, str) and torque == "auto")):
        raise InvalidInputError(
            f"torque must be 'auto', True or False, got {torque!r}", name="torque"
        )
    return torque


def checked_position_rows(position_rows: bool | str) -> bool | str:
    """``position_rows`` checked to be ``"auto"`` or True."""
    if not (position_rows is True or (isinstance(position_rows, str) and position_rows == "auto")):
        raise InvalidInputError(
            f"position_rows must be 'auto' or True, got {position_rows!r}",
            name="position_rows",
        )
    return position_rows
