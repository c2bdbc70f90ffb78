"""What every worker of a sweep needs to turn a shot into its row: the job, sent once.

A :class:`ShotJob` holds the planner (built once, in the parent), its registry name, the
per-shot time limit and whether planned shots are tracked in MuJoCo. Each executor sends it
to a worker once, and then sends only shots.
"""

from __future__ import annotations

from dataclasses import dataclass

from optraj.planners.base import Planner
from optraj.sweeps.row import error_row, plan_row
from optraj.sweeps.shots import Shot
from optraj.validation import as_flag

__all__ = ["ShotJob"]


@dataclass(frozen=True)
class ShotJob:
    """How to plan one shot of a sweep.

    Attributes:
        planner: The planner, from :func:`optraj.planners.registry.make_planner` for the
            shots' kind (``shot.kind``).
        name: Its registry name (the rows' ``planner`` column).
        seconds: Longest a shot may take [s], its outcome included; no limit when None.
        outcome: Track each planned shot in MuJoCo and judge it by the ball (the outcome
            columns, :data:`optraj.sweeps.columns.OUTCOME_COLUMNS`); None in those columns
            otherwise.

    Raises:
        InvalidInputError: ``outcome`` is not True or False.
    """

    planner: Planner
    name: str
    seconds: float | None = None
    outcome: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "outcome", as_flag(self.outcome, "outcome"))

    def row(self, shot: Shot) -> dict[str, object]:
        """Plan ``shot`` and return its row (never raises for the shot's sake)."""
        return plan_row(self.planner, self.name, shot, self.seconds, self.outcome)

    def error_row(
        self, shot: Shot, status: str, error_type: str, message: str
    ) -> dict[str, object]:
        """The row of ``shot`` when it produced no plan (stopped or its worker died)."""
        return error_row(shot, self.name, status, error_type, message)
