import os
import signal
import threading
import time

import cluster_support
import dask
import pytest
import sweeps_support
from distributed import Client, LocalCluster
from sweeps_support import SMALL, outcome

from optraj import sweeps
from optraj.errors import ClusterError, InvalidInputError
from optraj.sweeps import cluster, read_rows
from optraj.sweeps.processes import GRACE, WorkerStartError

#: 40 shots, about half of them refused at 0.9 m/s.
FORTY = sweeps.ShotSet(x=(0.65, 0.85), y=(-0.05, 0.3), grid=(4, 5), speeds=(0.3, 0.9))


def _local_cluster(workers=2):
    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",
    )


@pytest.fixture(scope="module")
def local_cluster():
    with _local_cluster() as started:
        yield started


@pytest.fixture(autouse=True)
def _cluster_planners(_misbehaving_planners):
    cluster_support.register()


@pytest.mark.slow
def test_serial_processes_and_dask_give_identical_tables(local_cluster, tmp_path):
    serial = sweeps.run(FORTY, planner="ruckig", workers=0, progress=False)
    pooled = sweeps.run(FORTY, planner="ruckig", workers=2, progress=False)
    out = tmp_path / "m.jsonl"
    on_dask = sweeps.run(
        FORTY, planner="ruckig", scheduler=local_cluster.scheduler_address, out=out, progress=False
    )
    assert len(serial) == 40 and {row["status"] for row in serial} == {"planned", "refused"}
    assert outcome(on_dask) == outcome(serial) == outcome(pooled)
    assert set(read_rows(out)) == {shot.shot_id for shot in FORTY}


def test_a_client_or_a_cluster_object_is_accepted_and_left_open(local_cluster):
    shots = SMALL.shots()[:3]
    serial = sweeps.run(shots, planner="ruckig", workers=0, progress=False)
    with Client(local_cluster, set_as_default=False) as client:
        assert outcome(sweeps.run(shots, planner="ruckig", scheduler=client)) == outcome(serial)
        assert client.status == "running"  # the caller's client stays open
    assert outcome(sweeps.run(shots, planner="ruckig", scheduler=local_cluster)) == outcome(serial)


def test_the_planner_is_sent_once_per_worker(local_cluster):
    rows = sweeps.run(
        FORTY.shots()[:12], planner="test-count", scheduler=local_cluster, chunk_size=1
    )
    assert len(rows) == 12
    with Client(local_cluster, set_as_default=False) as client:
        counts = client.run(cluster_support.loads)
    # one load per worker, however many of the 12 chunks it ran
    assert [count for _, count in counts.values()] == [1, 1]


@pytest.mark.slow
def test_raise_and_hangs_become_rows_with_their_reason(local_cluster):
    shots = SMALL.shots()[:2]
    failed = sweeps.run(shots, planner="test-raise", scheduler=local_cluster, progress=False)
    assert [row["error_message"] for row in failed] == ["forced failure"] * 2
    start = time.monotonic()
    spun = sweeps.run(
        shots, planner="test-spin", scheduler=local_cluster, time_limit=0.3, progress=False
    )
    assert [row["status"] for row in spun] == ["timed out"] * 2
    assert all(row["plan_time"] < GRACE for row in spun)  # stopped inside the worker
    assert all("restarted" not in row["error_message"] for row in spun)
    # 1 s: the problem is built within the limit (while other tests load the cores) before
    # the planner gets stuck where the limit cannot reach it.
    stuck = sweeps.run(
        shots[:1], planner="test-stuck", scheduler=local_cluster, time_limit=1.0, progress=False
    )
    assert stuck[0]["status"] == "timed out" and "worker was restarted" in stuck[0]["error_message"]
    assert time.monotonic() - start < 30.0
    after = sweeps.run(shots, planner="ruckig", scheduler=local_cluster, progress=False)
    assert [row["status"] for row in after] == ["planned", "refused"]  # the cluster works on


@pytest.mark.slow
def test_a_worker_killed_mid_sweep_loses_no_shot(tmp_path):
    shots = FORTY.shots()[:16]
    out = tmp_path / "m.jsonl"
    with _local_cluster() as started, Client(started, set_as_default=False) as client:
        pids = list(client.run(os.getpid).values())
        result = {}

        def sweep():
            result["rows"] = sweeps.run(
                shots, planner="test-slow", scheduler=client, out=out, chunk_size=2
            )

        thread = threading.Thread(target=sweep)
        thread.start()
        deadline = time.monotonic() + 60.0
        while len(read_rows(out)) < 2 and time.monotonic() < deadline:
            time.sleep(0.02)
        done = len(read_rows(out))
        os.kill(pids[0], signal.SIGKILL)
        thread.join(120.0)
    assert not thread.is_alive() and 2 <= done < len(shots)  # killed half-way
    rows = result["rows"]
    assert [row["shot_id"] for row in rows] == [shot.shot_id for shot in shots]
    lines = out.read_text().splitlines()
    assert len(lines) == len(shots)  # every shot exactly once
    serial = sweeps.run(shots, planner="ruckig", workers=0, progress=False)
    assert [row["status"] for row in rows] == [row["status"] for row in serial]


@pytest.mark.slow
def test_a_shot_that_kills_its_worker_each_time_is_a_failed_row():
    shots = SMALL.shots()[:1]
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}), _local_cluster(1) as c:
        from optraj.planners import registry

        registry.register_planner("pool-shot", "test-die", sweeps_support.Dying)
        rows = sweeps.run(shots, planner="test-die", scheduler=c, progress=False)
    assert rows[0]["status"] == "failed" and rows[0]["error_type"] == "WorkerDied"


def test_a_planner_the_workers_cannot_load_stops_the_sweep(local_cluster):
    from optraj.planners import registry

    registry.register_planner("pool-shot", "test-unloadable", sweeps_support.FailsToLoad)
    with pytest.raises(WorkerStartError, match=r"could not load the planner.*does not load here"):
        sweeps.run(SMALL, planner="test-unloadable", scheduler=local_cluster)
    rows = sweeps.run(SMALL.shots()[:1], planner="ruckig", scheduler=local_cluster)
    assert rows[0]["status"] == "planned"  # the cluster is left as it was


def test_bad_schedulers_are_refused(monkeypatch):
    with pytest.raises(InvalidInputError, match=r"scheduler must be .* got 42"):
        sweeps.run(SMALL, planner="ruckig", scheduler=42)
    with pytest.raises(InvalidInputError, match="give workers or scheduler, not both"):
        sweeps.run(SMALL, planner="ruckig", workers=2, scheduler="tcp://127.0.0.1:1")
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    with pytest.raises(ClusterError, match=r"no Dask scheduler answered at 'tcp://127.0.0.1:9'"):
        sweeps.run(SMALL, planner="ruckig", scheduler="tcp://127.0.0.1:9")


@pytest.mark.slow
def test_the_map_command_plans_on_a_scheduler_address(local_cluster, tmp_path):
    from io import StringIO

    from optraj import cli

    out = tmp_path / "map.parquet"
    printed = StringIO()
    argv = ["map", "sawyer", "--grid", "2x2", "--speeds", "0.3,0.9", "--planner", "ruckig"]
    argv += ["--x", "0.7,0.8", "--y", "0.0,0.2", "--out", str(out)]
    status = cli.main([*argv, "--scheduler", local_cluster.scheduler_address], out=printed)
    assert status == 0, printed.getvalue()
    serial = sweeps.run(SMALL, planner="ruckig", workers=0, progress=False)
    on_dask = sweeps.read_parquet(out)
    assert sorted(outcome(on_dask), key=lambda r: r["shot_id"]) == sorted(
        outcome(serial), key=lambda r: r["shot_id"]
    )
