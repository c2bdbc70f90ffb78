"""The local-process executor: shots in chunks over a pool of spawned worker processes.

Each worker receives the planner once, when it starts (the pool's initializer), and then
plans chunks of shots. It reports the start of each shot and each row on a queue kept by a
manager process, so rows arrive one by one. A shot that runs past the time limit is first
interrupted inside its worker (:func:`optraj.sweeps.time_limit.time_limit`); one stuck
where that cannot reach (inside a C library) is stopped from outside after :data:`GRACE`
more seconds by killing its worker: the shot becomes a ``timed out`` row, and a new pool
plans the shots left (the other workers' shots in progress start again). A worker that
dies on its own costs its shot one attempt; after :data:`ATTEMPTS` the shot is a
``failed`` row. Workers run their BLAS and OpenMP libraries on one thread each
(:data:`THREAD_VARIABLES`), as Dask's workers do.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import signal
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from optraj.sweeps.job import ShotJob
from optraj.sweeps.shots import Shot

__all__ = [
    "ATTEMPTS",
    "GRACE",
    "MAX_CHUNK",
    "THREAD_VARIABLES",
    "WorkerStartError",
    "chunks",
    "default_chunk_size",
    "run_processes",
]

#: Seconds past the time limit before a stuck shot's worker is killed [s].
GRACE = 2.0
#: Worker deaths a shot may go through before it is recorded as failed.
ATTEMPTS = 2
#: Most shots in one chunk sent to a worker.
MAX_CHUNK = 16
#: Seconds the parent waits on the queue before it looks for stuck shots [s].
POLL = 0.05

_WORKER: dict[str, Any] = {}


class WorkerStartError(RuntimeError):
    """The worker processes stopped before planning any shot (the planner did not load)."""


def _start_worker(job: ShotJob, messages: Any) -> None:
    _WORKER.update(job=job, messages=messages)


def _plan_chunk(chunk: list[Shot]) -> None:
    messages = _WORKER["messages"]
    for shot in chunk:
        messages.put(("start", shot.shot_id, os.getpid(), None))
        row = _WORKER["job"].row(shot)
        messages.put(("row", shot.shot_id, os.getpid(), row))


def chunks(shots: Sequence[Shot], size: int) -> list[list[Shot]]:
    """``shots`` cut in order into lists of ``size`` (the last may be shorter)."""
    return [list(shots[i : i + size]) for i in range(0, len(shots), size)]


#: The environment variables that size the thread pools of BLAS and OpenMP libraries.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


@contextmanager
def _threads_per_worker() -> Iterator[None]:
    """Spawn workers whose BLAS and OpenMP libraries run one thread each, as Dask's do.

    The solves of one shot are small: more threads per worker only contend for the cores
    the other workers use. A variable the user has set is left as it is.
    """
    unset = [name for name in THREAD_VARIABLES if name not in os.environ]
    for name in unset:
        os.environ[name] = "1"
    try:
        yield
    finally:
        for name in unset:
            os.environ.pop(name, None)


def default_chunk_size(shots: int, workers: int) -> int:
    """Shots per chunk: about four chunks per worker, at most :data:`MAX_CHUNK`."""
    return max(1, min(MAX_CHUNK, -(-shots // (4 * max(workers, 1)))))


@dataclass
class _Round:
    """What one pool saw: the shot each worker is on, and whether any row came in."""

    running: dict[int, tuple[str, float]] = field(default_factory=dict)
    progressed: bool = False
    killed: bool = False


@dataclass
class _Sweep:
    """The shots still to plan, and how to record a row."""

    pending: dict[str, Shot]
    job: ShotJob
    on_row: Callable[[dict[str, object]], None]
    attempts: dict[str, int] = field(default_factory=dict)

    def record(self, shot_id: str, row: dict[str, object]) -> None:
        """Record the row of a pending shot (a late row of a recorded shot is dropped)."""
        if self.pending.pop(shot_id, None) is not None:
            self.on_row(row)


def run_processes(
    shots: Sequence[Shot],
    job: ShotJob,
    on_row: Callable[[dict[str, object]], None],
    *,
    workers: int,
    chunk_size: int,
) -> None:
    """Plan ``shots`` as ``job`` says in ``workers`` spawned processes; rows to ``on_row``.

    Raises:
        WorkerStartError: The workers could not start (e.g. the planner does not unpickle).
    """
    sweep = _Sweep({shot.shot_id: shot for shot in shots}, job, on_row)
    context = multiprocessing.get_context("spawn")
    with _threads_per_worker(), context.Manager() as manager:
        while sweep.pending:
            # A manager's queue sends each message at once: a shot's start is known even
            # when its worker dies right after.
            messages = manager.Queue()
            setup = (job, messages)
            with ProcessPoolExecutor(workers, context, _start_worker, setup) as pool:
                work = chunks(list(sweep.pending.values()), chunk_size)
                futures = [pool.submit(_plan_chunk, chunk) for chunk in work]
                state = _watch(sweep, messages, futures, job.seconds)
            _drain(sweep, messages, state)
            if sweep.pending and not (state.progressed or state.killed or state.running):
                errors = [f.exception() for f in futures if f.done() and f.exception()]
                raise WorkerStartError("the worker processes stopped before any shot") from (
                    errors[0] if errors else None
                )
            _count_deaths(sweep, state)


def _watch(
    sweep: _Sweep, messages: Any, futures: list[Future[None]], seconds: float | None
) -> _Round:
    """Take rows off the queue until every shot has one or the pool breaks."""
    state = _Round()
    while sweep.pending:
        try:
            _take(sweep, state, messages.get(timeout=POLL))
            continue
        except queue.Empty:
            pass
        if seconds is not None and _kill_stuck(sweep, state, seconds):
            break
        if any(f.done() and f.exception() is not None for f in futures):
            break  # a worker died: the pool is broken
    return state


def _take(sweep: _Sweep, state: _Round, message: tuple[str, str, int, Any]) -> None:
    kind, shot_id, pid, row = message
    if kind == "start":
        state.running[pid] = (shot_id, time.monotonic())
        return
    state.running.pop(pid, None)
    state.progressed = True
    sweep.record(shot_id, row)


def _kill_stuck(sweep: _Sweep, state: _Round, seconds: float) -> bool:
    """Kill the worker of a shot past the time limit plus :data:`GRACE`; whether it did."""
    now = time.monotonic()
    for pid, (shot_id, started) in list(state.running.items()):
        if now - started > seconds + GRACE and shot_id in sweep.pending:
            os.kill(pid, getattr(signal, "SIGKILL", signal.SIGTERM))
            del state.running[pid]
            shot = sweep.pending[shot_id]
            message = f"the shot ran past the time limit of {seconds:.6g} s; its worker was killed"
            sweep.record(shot_id, sweep.job.error_row(shot, "timed out", "ShotTimeout", message))
            state.killed = True
            return True
    return False


def _drain(sweep: _Sweep, messages: Any, state: _Round) -> None:
    """Take the rows still on the queue after the pool stopped."""
    while True:
        try:
            _take(sweep, state, messages.get(timeout=POLL))
        except queue.Empty:
            return


def _count_deaths(sweep: _Sweep, state: _Round) -> None:
    """Charge the shots whose worker died one attempt; record those out of attempts."""
    if state.killed:
        return  # the other workers were stopped with the pool, not by their shots
    for shot_id, _ in state.running.values():
        if shot_id not in sweep.pending:
            continue
        sweep.attempts[shot_id] = sweep.attempts.get(shot_id, 0) + 1
        if sweep.attempts[shot_id] >= ATTEMPTS:
            shot = sweep.pending[shot_id]
            message = f"the worker process died during the shot ({ATTEMPTS} times)"
            sweep.record(shot_id, sweep.job.error_row(shot, "failed", "WorkerDied", message))
