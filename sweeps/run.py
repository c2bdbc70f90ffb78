"""Run a sweep: plan every shot of a set, serially or in local processes, with resume.

>>> from optraj import sweeps
>>> shots = sweeps.ShotSet(grid=(2, 2), speeds=(0.3,))
>>> rows = sweeps.run(shots, planner="ruckig", workers=2, out="map.jsonl")  # doctest: +SKIP
>>> [row["status"] for row in rows]                                         # doctest: +SKIP
['planned', 'planned', 'planned', 'refused']

With ``out``, each row is appended to that JSON-lines file as it arrives, and a run given
the same ``out`` again plans only the shots that have no row there yet.
"""

from __future__ import annotations

import importlib
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from types import ModuleType

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.planners.registry import make_planner
from optraj.sweeps.job import ShotJob
from optraj.sweeps.processes import default_chunk_size, run_processes
from optraj.sweeps.progress import Progress
from optraj.sweeps.serial import run_serial
from optraj.sweeps.shots import Shot
from optraj.sweeps.store import RowFile, read_rows
from optraj.validation import MAX_DURATION, as_count, as_flag, as_positive

__all__ = ["MAX_WORKERS", "run"]

#: Most worker processes a sweep may start.
MAX_WORKERS = 1024


def _shots(shots: Iterable[Shot]) -> list[Shot]:
    """The shots as a list; refuses anything that is not a Shot, and repeated ids."""
    try:
        found = list(shots)
    except TypeError as exc:
        raise InvalidInputError(
            f"shots must be a ShotSet or an iterable of Shot, got {type(shots).__name__}",
            name="shots",
        ) from exc
    seen: set[str] = set()
    for shot in found:
        if not isinstance(shot, Shot):
            raise InvalidInputError(
                f"shots must hold Shot records, got {type(shot).__name__}", name="shots"
            )
        if shot.shot_id in seen:
            raise InvalidInputError(f"shot {shot.shot_id!r} is given twice", name="shots")
        seen.add(shot.shot_id)
    return found


def _workers(workers: int | None) -> int:
    if workers is None:
        return os.cpu_count() or 1
    return as_count(workers, "workers", 0, MAX_WORKERS)


def run(
    shots: Iterable[Shot],
    planner: str = "optimal-control",
    *,
    options: Mapping[str, object] | None = None,
    workers: int | None = None,
    scheduler: object | None = None,
    out: str | os.PathLike[str] | None = None,
    time_limit: float | None = None,
    chunk_size: int | None = None,
    max_shots: int | None = None,
    outcome: bool = False,
    progress: bool = True,
) -> list[dict[str, object]]:
    """Plan every shot and return one row per shot (:data:`optraj.sweeps.COLUMNS`).

    Args:
        shots: A :class:`optraj.sweeps.ShotSet` or :class:`optraj.sweeps.PaddleShotSet`, or
            any iterable of :class:`Shot` of one kind.
        planner: The name in :mod:`optraj.planners.registry` of a planner of the shots' kind
            (``"pool-shot"`` or ``"paddle-strike"``).
        options: The planner's own options (``registry.options(kind, planner)``).
        workers: Local worker processes; all cores when None, 0 for serial in this process.
        scheduler: A Dask ``distributed.Client``, a Dask cluster object or a scheduler
            address (``"tcp://HOST:PORT"``): plan on that cluster instead of local
            processes (``workers`` must then be None). Needs the ``sweeps`` extra.
        out: A JSON-lines file the rows are appended to as they arrive; shots that already
            have a row there are not planned again (their rows are returned as read). It
            must hold rows of this planner only.
        time_limit: Longest a shot may take [s] before it is stopped and recorded
            ``timed out``; none when None.
        chunk_size: Shots sent to a worker at a time; by default enough for about four
            chunks per worker, at most 16.
        max_shots: Plan at most this many new shots in this run (the rest are left for a
            later run with the same ``out``); all when None.
        outcome: Track each planned shot in MuJoCo and record where the ball went
            (:data:`optraj.sweeps.OUTCOME_COLUMNS`; about a second more per shot).
        progress: Draw a progress bar on stderr.

    Returns:
        The rows of the shots that have one, in the order of ``shots``.

    Raises:
        InvalidInputError: Bad shots, workers, scheduler, time limit, chunk size, shot limit
            or option, an ``out`` file with rows of another planner, shots of more than one
            kind, or both ``workers`` and ``scheduler``.
        UnknownNameError: A planner that does not plan the shots' kind.
        ClusterError: No Dask scheduler answers at ``scheduler``, or it has no worker.
        MissingDependencyError: ``scheduler`` given without Dask ``distributed`` installed.
    """
    found = _shots(shots)
    if scheduler is not None and workers is not None:
        raise InvalidInputError(
            f"give workers or scheduler, not both (got workers={workers!r})", name="workers"
        )
    count = _workers(workers)
    show = as_flag(progress, "progress")
    limit = len(found) if max_shots is None else as_count(max_shots, "max_shots")
    job = _job(found, planner, options, time_limit, outcome)
    rows = _done(out, planner)
    todo = [shot for shot in found if shot.shot_id not in rows][:limit]
    size = None if chunk_size is None else as_count(chunk_size, "chunk_size", 1)
    bar = Progress(len(todo), show)
    try:
        with RowFile(out) as file:

            def on_row(row: dict[str, object]) -> None:
                file.write(row)
                rows[str(row["shot_id"])] = row
                bar.advance()

            if scheduler is not None and todo:
                _cluster().run_dask(todo, job, on_row, scheduler=scheduler, chunk_size=size)
            elif count == 0 or not todo:
                run_serial(todo, job, on_row)
            else:
                size = size or default_chunk_size(len(todo), count)
                workers_used = min(count, math.ceil(len(todo) / size))
                run_processes(todo, job, on_row, workers=workers_used, chunk_size=size)
    finally:
        bar.close()  # a sweep that raises leaves no open bar line
    return [rows[shot.shot_id] for shot in found if shot.shot_id in rows]


def _job(
    shots: list[Shot],
    planner: str,
    options: Mapping[str, object] | None,
    time_limit: float | None,
    outcome: bool,
) -> ShotJob:
    """The job of the sweep: the planner of the shots' one kind, the limit, the outcome."""
    kinds = sorted({shot.kind for shot in shots})
    if len(kinds) > 1:
        raise InvalidInputError(
            f"the shots of one sweep must be of one kind, got {', '.join(kinds)}", name="shots"
        )
    kind = kinds[0] if kinds else "pool-shot"
    seconds = (
        None if time_limit is None else as_positive(time_limit, "time_limit", "s", MAX_DURATION)
    )
    made = make_planner(kind, planner, **dict(options or {}))
    return ShotJob(made, planner, seconds, as_flag(outcome, "outcome"))


def _done(out: str | os.PathLike[str] | None, planner: str) -> dict[str, dict[str, object]]:
    """The rows already in ``out``; refuses a file of another planner's rows."""
    if out is None:
        return {}
    rows = read_rows(Path(out))
    others = sorted({str(row.get("planner")) for row in rows.values()} - {planner})
    if others:
        raise InvalidInputError(
            f"out {str(out)!r} holds rows of planner {others[0]!r}, not {planner!r}: "
            "resume with that planner or write to another file",
            name="out",
        )
    return rows


def _cluster() -> ModuleType:
    """The Dask executor's module; refuses when Dask ``distributed`` is not installed."""
    try:
        return importlib.import_module("optraj.sweeps.cluster")
    except ImportError as exc:
        if (exc.name or "").split(".")[0] not in {"distributed", "dask"}:
            raise
        raise MissingDependencyError("distributed", "sweeps", "sweeps.run(scheduler=...)") from exc
