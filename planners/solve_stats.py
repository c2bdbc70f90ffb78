"""What a plan cost and how its solver ended, typed: :class:`SolveStats`, read off a trajectory.

Every planner stamps ``traj.metadata`` (a dict that also round-trips through JSON); this is its
typed, documented view, the same for every planner, with ``None`` where a planner has no such
number (a cubic has no solver iterations):

>>> stats = planners.SolveStats.of(planners.OptimalControl().plan(problem))
>>> stats.iterations, stats.solver_status, stats.solve_time        # 33 'Solve_Succeeded' 0.36
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from optraj.errors import InvalidInputError

__all__ = ["SolveStats"]


def _integer(metadata: Mapping[str, Any], key: str) -> int | None:
    value = metadata.get(key)
    return None if value is None or isinstance(value, bool) else int(value)


def _real(metadata: Mapping[str, Any], key: str) -> float | None:
    value = metadata.get(key)
    if value is None or isinstance(value, bool):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def _text(metadata: Mapping[str, Any], key: str) -> str | None:
    value = metadata.get(key)
    return None if value is None else str(value)


def _flag(metadata: Mapping[str, Any], key: str) -> bool | None:
    value = metadata.get(key)
    return None if value is None else bool(value)


@dataclass(frozen=True)
class SolveStats:
    """The solve statistics of one plan; ``None`` where the planner has no such number.

    Attributes:
        planner: The planner's name (``metadata["planner"]``).
        status: ``"ok"`` for every returned plan (failures raise instead).
        solve_time: Wall time of ``plan`` [s].
        solver: The numerical solver (``"ipopt"`` for optimal control).
        solver_status: The solver's own final status (IPOPT's ``Solve_Succeeded``, ...).
        iterations: Solver iterations, summed over every solve of the plan.
        rounds: Solves of the refinement rounds (optimal control: more intervals where the
            tool left its tolerance, or torque rows added).
        objective: The objective's value at the solution (minimum time: the motion time [s];
            minimum jerk: the weighted integral of squared jerk).
        constraint_violation: The largest row violation the solver reports at the solution.
        nlp_time: Wall time inside the NLP solver [s], all rounds.
        evaluation_time: The part of ``nlp_time`` spent evaluating the NLP's functions and
            derivatives [s].
        contact_time: Wall time of the contact choice of a strike [s] (0 for a move).
        warm_started: Whether the first solve started from a previous solution.
        solves: TOPPRA: how many times the path was retimed (slowed down to meet jerk).
        gridpoints: TOPPRA: the grid intervals along the path.
    """

    planner: str
    status: str
    solve_time: float | None = None
    solver: str | None = None
    solver_status: str | None = None
    iterations: int | None = None
    rounds: int | None = None
    objective: float | None = None
    constraint_violation: float | None = None
    nlp_time: float | None = None
    evaluation_time: float | None = None
    contact_time: float | None = None
    warm_started: bool | None = None
    solves: int | None = None
    gridpoints: int | None = None

    @classmethod
    def of(cls, trajectory: Any) -> SolveStats:
        """The statistics a planner stamped on ``trajectory`` (its ``metadata``).

        Raises:
            InvalidInputError: ``trajectory`` has no metadata mapping, or no planner stamped
                it (no ``planner`` key).
        """
        metadata = getattr(trajectory, "metadata", None)
        if not isinstance(metadata, Mapping):
            raise InvalidInputError(
                f"SolveStats.of needs a planners.Trajectory, got {type(trajectory).__name__}",
                name="trajectory",
            )
        if "planner" not in metadata:
            raise InvalidInputError(
                "the trajectory's metadata names no planner: it was not made by a planner's "
                "plan (or its metadata was replaced)",
                name="trajectory",
            )
        return cls(
            planner=str(metadata["planner"]),
            status=str(metadata.get("status", "ok")),
            solve_time=_real(metadata, "solve_time"),
            solver=_text(metadata, "solver"),
            solver_status=_text(metadata, "solver_status"),
            iterations=_integer(metadata, "iterations"),
            rounds=_integer(metadata, "rounds"),
            objective=_real(metadata, "objective"),
            constraint_violation=_real(metadata, "constraint_violation"),
            nlp_time=_real(metadata, "nlp_time"),
            evaluation_time=_real(metadata, "evaluation_time"),
            contact_time=_real(metadata, "contact_time"),
            warm_started=_flag(metadata, "warm_started"),
            solves=_integer(metadata, "solves"),
            gridpoints=_integer(metadata, "gridpoints"),
        )
