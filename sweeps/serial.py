"""The serial executor: every shot in this process, one after another (for debugging)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from optraj.sweeps.job import ShotJob
from optraj.sweeps.shots import Shot

__all__ = ["run_serial"]


def run_serial(
    shots: Sequence[Shot], job: ShotJob, on_row: Callable[[dict[str, object]], None]
) -> None:
    """Plan each shot as ``job`` says and pass its row to ``on_row``.

    The job's time limit interrupts Python code only (see
    :func:`optraj.sweeps.time_limit.time_limit`).
    """
    for shot in shots:
        on_row(job.row(shot))
