"""The Dask executor: shots in chunks on a ``distributed`` cluster.

The job (planner, name, time limit) reaches each worker once, as a worker plugin, so a
worker that joins or restarts mid-sweep receives it too; each task then carries only a
chunk of shots and returns its rows. Dask reschedules the chunk of a worker that dies; a
chunk whose workers keep dying (:class:`distributed.KilledWorker`) is retried shot by shot,
and a shot that still kills its worker becomes a ``failed`` row.

Each shot runs on a thread of its own inside the task. Python code past the time limit is
interrupted there (:func:`optraj.sweeps.time_limit.time_limit`); a shot stuck where that
cannot reach (a sleep, a call inside a C library) is given :data:`GRACE` more seconds, then
recorded ``timed out``: the task returns at once with the shots of its chunk left unplanned,
and the worker is restarted to free the stuck thread (its other work is rescheduled).
"""

from __future__ import annotations

import threading
import uuid
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import distributed

from optraj.errors import ClusterError, InvalidInputError
from optraj.sweeps.job import ShotJob
from optraj.sweeps.processes import GRACE, WorkerStartError, chunks, default_chunk_size
from optraj.sweeps.shots import Shot

__all__ = ["CONNECT_TIMEOUT", "connect", "run_dask"]

#: Longest wait for the scheduler to answer and for a first worker [s].
CONNECT_TIMEOUT = 10.0


class _JobPlugin(distributed.WorkerPlugin):
    """Holds a sweep's job on every worker."""

    def __init__(self, job: ShotJob) -> None:
        self.job = job


@dataclass
class _Chunk:
    """What a task returns: the rows it made, the shots it left, the worker to restart."""

    rows: list[dict[str, object]]
    left: list[Shot] = field(default_factory=list)
    stuck_on: str | None = None


def _row_within(job: ShotJob, shot: Shot) -> dict[str, object] | None:
    """The shot's row, or None when it is still running :data:`GRACE` s past the limit."""
    if job.seconds is None:
        return job.row(shot)
    rows: list[dict[str, object]] = []
    thread = threading.Thread(target=lambda: rows.append(job.row(shot)), daemon=True)
    thread.start()
    thread.join(job.seconds + GRACE)
    return rows[0] if rows else None


def _plan_chunk(plugin: str, chunk: list[Shot]) -> _Chunk:
    """Plan a chunk on a worker with the job its plugin holds (runs on the worker)."""
    worker = distributed.get_worker()
    job: ShotJob = worker.plugins[plugin].job  # type: ignore[attr-defined]  # our plugin
    rows = []
    for index, shot in enumerate(chunk):
        row = _row_within(job, shot)
        if row is None:
            message = (
                f"the shot ran past the time limit of {job.seconds:.6g} s; its worker was restarted"
            )
            rows.append(job.error_row(shot, "timed out", "ShotTimeout", message))
            return _Chunk(rows, chunk[index + 1 :], worker.address)
        rows.append(row)
    return _Chunk(rows)


def connect(scheduler: object) -> tuple[distributed.Client, bool]:
    """A client of ``scheduler`` and whether it was opened here (and must be closed here).

    Args:
        scheduler: A ``distributed.Client``, a cluster object with a ``scheduler_address``
            (e.g. ``distributed.LocalCluster``), or an address such as ``"tcp://HOST:PORT"``.

    Raises:
        InvalidInputError: ``scheduler`` is none of these.
        ClusterError: No scheduler answers at the address, or it has no worker, within
            :data:`CONNECT_TIMEOUT`.
    """
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    address = getattr(scheduler, "scheduler_address", scheduler)
    if not isinstance(address, str) or "://" not in address:
        raise InvalidInputError(
            "scheduler must be a distributed.Client, a Dask cluster or an address such as "
            f"'tcp://HOST:PORT', got {scheduler!r}",
            name="scheduler",
            value=scheduler,
        )
    try:
        client = distributed.Client(address, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise ClusterError(
            f"no Dask scheduler answered at {address!r} within {CONNECT_TIMEOUT:g} s",
            address=address,
        ) from exc
    return client, True


def _threads(client: distributed.Client) -> int:
    """Worker threads in the cluster, after waiting for at least one worker."""
    try:
        client.wait_for_workers(1, timeout=CONNECT_TIMEOUT)
    except TimeoutError as exc:
        raise ClusterError(
            f"the Dask scheduler at {client.scheduler.address!r} has no worker "
            f"after {CONNECT_TIMEOUT:g} s",
            address=client.scheduler.address,
        ) from exc
    return max(1, sum(client.nthreads().values()))


def run_dask(
    shots: Sequence[Shot],
    job: ShotJob,
    on_row: Callable[[dict[str, object]], None],
    *,
    scheduler: object,
    chunk_size: int | None = None,
) -> None:
    """Plan ``shots`` as ``job`` says on the Dask cluster ``scheduler``; rows to ``on_row``.

    Args:
        shots: The shots to plan.
        job: The planner, its name and the time limit.
        on_row: Called with each row as its chunk arrives.
        scheduler: As :func:`connect`.
        chunk_size: Shots per task; by default about four chunks per worker thread.

    Raises:
        InvalidInputError, ClusterError: As :func:`connect`.
        WorkerStartError: The workers cannot load the job (e.g. the planner does not
            unpickle there).
    """
    client, opened = connect(scheduler)
    try:
        size = chunk_size or default_chunk_size(len(shots), _threads(client))
        _Sweep(client, job, on_row).run(shots, size)
    finally:
        if opened:
            client.close()


class _Sweep:
    """The shots in flight on the cluster and the rows recorded."""

    def __init__(
        self,
        client: distributed.Client,
        job: ShotJob,
        on_row: Callable[[dict[str, object]], None],
    ) -> None:
        self.client = client
        self.job = job
        self.on_row = on_row
        self.plugin = f"optraj-sweep-{uuid.uuid4().hex}"
        self.work = distributed.as_completed(loop=client.loop)
        self.chunks: dict[object, list[Shot]] = {}
        self.pending: set[str] = set()

    def run(self, shots: Sequence[Shot], size: int) -> None:
        """Submit ``shots`` in chunks of ``size`` and record every row."""
        self.pending = {shot.shot_id for shot in shots}
        try:
            self.client.register_plugin(_JobPlugin(self.job), name=self.plugin)
        except Exception as exc:  # the scheduler passes a worker's error on as Exception
            self._forget()
            raise WorkerStartError(f"the Dask workers could not load the planner: {exc}") from exc
        try:
            for chunk in chunks(shots, size):
                self._submit(chunk)
            for future in self.work:
                self._take(future)
        finally:
            self._forget()

    def _forget(self) -> None:
        """Take the job off the workers (and off any that join later)."""
        try:
            self.client.unregister_worker_plugin(self.plugin)
        except Exception:  # never registered, or the cluster is gone: nothing to undo
            return

    def _submit(self, chunk: list[Shot]) -> None:
        future = self.client.submit(_plan_chunk, self.plugin, chunk, pure=False)
        self.chunks[future.key] = chunk
        self.work.add(future)

    def _take(self, future: Any) -> None:
        chunk = self.chunks.pop(future.key)
        try:
            result: _Chunk = future.result()
        except distributed.KilledWorker:
            self._killed(chunk)
            return
        for row in result.rows:
            self._record(row)
        if result.left:
            self._submit(result.left)
        if result.stuck_on is not None:
            self._restart(result.stuck_on)

    def _killed(self, chunk: list[Shot]) -> None:
        """A chunk whose workers died: retry its shots one by one, or record the one."""
        if len(chunk) > 1:
            for shot in chunk:
                self._submit([shot])
            return
        message = "the worker process died during the shot each time it was tried"
        self._record(self.job.error_row(chunk[0], "failed", "WorkerDied", message))

    def _record(self, row: dict[str, object]) -> None:
        shot_id = str(row["shot_id"])
        if shot_id in self.pending:
            self.pending.discard(shot_id)
            self.on_row(row)

    def _restart(self, address: str) -> None:
        try:
            self.client.restart_workers([address], timeout=CONNECT_TIMEOUT * 3)
        except Exception as exc:  # a worker without a nanny cannot restart
            warnings.warn(
                f"could not restart the Dask worker {address} after a stuck shot ({exc}); "
                "its stuck thread keeps running",
                RuntimeWarning,
                stacklevel=2,
            )
