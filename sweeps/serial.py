"""The serial executor: every shot in this process, one after another (for debugging)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from optraj.planners.base import Planner
from optraj.sweeps.row import plan_row
from optraj.sweeps.shots import Shot

__all__ = ["run_serial"]


def run_serial(
    shots: Sequence[Shot],
    planner: Planner,
    name: str,
    seconds: float | None,
    on_row: Callable[[dict[str, object]], None],
) -> None:
    """Plan each shot with ``planner`` (registry name ``name``) and pass its row to ``on_row``.

    The time limit ``seconds`` interrupts Python code only (see
    :func:`optraj.sweeps.time_limit.time_limit`).
    """
    for shot in shots:
        on_row(plan_row(planner, name, shot, seconds))
