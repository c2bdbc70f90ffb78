import time

import pytest
import sweeps_support
from sweeps_support import SMALL, outcome

from optraj.planners import registry
from optraj.sweeps.job import ShotJob
from optraj.sweeps.processes import ATTEMPTS, GRACE, WorkerStartError, chunks, run_processes
from optraj.sweeps.serial import run_serial

SHOTS = SMALL.shots()


def _run(planner, name, shots, seconds=None, workers=2, chunk_size=2):
    rows = []
    job = ShotJob(planner, name, seconds)
    run_processes(shots, job, rows.append, workers=workers, chunk_size=chunk_size)
    return rows


@pytest.mark.slow
def test_two_processes_give_the_serial_rows():
    planner = registry.make_planner("pool-shot", "ruckig")
    serial = []
    run_serial(SHOTS, ShotJob(planner, "ruckig"), serial.append)
    rows = _run(planner, "ruckig", SHOTS, workers=2, chunk_size=3)
    order = {shot.shot_id: i for i, shot in enumerate(SHOTS)}
    rows.sort(key=lambda row: order[row["shot_id"]])
    assert outcome(rows) == outcome(serial)
    assert {row["status"] for row in rows} == {"planned", "refused"}


@pytest.mark.slow
def test_a_raise_and_a_python_hang_become_rows():
    failed = _run(sweeps_support.Raising(), "test-raise", SHOTS[:2])
    assert [row["status"] for row in failed] == ["failed", "failed"]
    assert failed[0]["error_message"] == "forced failure"
    hung = _run(sweeps_support.Sleeping(), "test-sleep", SHOTS[:2], seconds=0.3)
    assert [row["status"] for row in hung] == ["timed out", "timed out"]
    assert all(row["plan_time"] < GRACE for row in hung)  # stopped inside the worker


@pytest.mark.slow
def test_a_stuck_worker_is_killed_and_the_other_shots_planned_once():
    shots = SHOTS[:4]
    start = time.monotonic()
    # 2 s: the shots that plan stay within the limit while other tests load the cores.
    rows = _run(sweeps_support.StuckOnOne(), "ruckig", shots, seconds=2.0, chunk_size=1)
    assert time.monotonic() - start < 30.0
    assert sorted(row["shot_id"] for row in rows) == sorted(shot.shot_id for shot in shots)
    stuck = [row for row in rows if row["status"] == "timed out"]
    assert [row["shot_id"] for row in stuck] == [shots[1].shot_id]
    assert "worker was killed" in stuck[0]["error_message"]
    assert {row["status"] for row in rows} - {"timed out"} <= {"planned", "refused"}


def test_a_worker_that_dies_fails_its_shot_after_the_attempts():
    rows = _run(sweeps_support.Dying(), "test-die", SHOTS[:1], workers=1)
    assert rows[0]["status"] == "failed" and rows[0]["error_type"] == "WorkerDied"
    assert f"{ATTEMPTS} times" in rows[0]["error_message"]


def test_a_planner_that_does_not_load_in_the_workers():
    with pytest.raises(WorkerStartError, match="before any shot"):
        _run(sweeps_support.FailsToLoad(), "x", SHOTS[:1], workers=1)


def test_chunks_keep_the_order():
    assert chunks(list(range(5)), 2) == [[0, 1], [2, 3], [4]]


def test_workers_run_one_blas_thread_unless_the_user_says_otherwise(monkeypatch):
    import os

    import cluster_support

    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    rows = _run(cluster_support.ThreadsReporting(), "test-threads", SHOTS[:1], workers=1)
    assert rows[0]["error_message"] == "1,1,1"
    assert "OMP_NUM_THREADS" not in os.environ  # the parent's environment is put back
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    rows = _run(cluster_support.ThreadsReporting(), "test-threads", SHOTS[:1], workers=1)
    assert rows[0]["error_message"] == "3,1,1"
