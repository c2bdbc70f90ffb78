"""Sweep throughput: shots per second against workers, in local processes and on Dask.

One seeded set of random Sawyer pool shots is planned serially in this process, then in
local processes and on a Dask ``LocalCluster`` on loopback with 1, 2 and all of the
machine's cores as workers; every run must give the serial table (statuses, motion times,
binding joints). Reported, as ratios of the same run:

* parallel efficiency: serial wall time / (workers x wall time), target >= 0.85 at 2
  workers on 2 cores; local processes pay their start (spawn, import, first solve) in every
  run, the Dask cluster is started and warmed up once, as a user's cluster is;
* Dask's overhead per shot against local processes at the same workers, as a share of one
  shot's serial plan time (target <= 5 %);
* what a map of a million shots would take on N machines, from the measured cost per shot.

Usage: ``python benchmarks/sweep.py [--quick] [--shots N] [--planner NAME] [--out PATH]``
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from benchmarking import shot_arguments, write_report
from optraj import sweeps

RESULTS = Path(__file__).resolve().parent / "results"
#: Random shots of the full run; the planner and its cost per shot.
SHOTS = 64
PLANNER = "optimal-control"
#: Shots and planner of ``--quick`` (for CI).
QUICK_SHOTS = 8
QUICK_PLANNER = "ruckig"
#: Machines of the million-shot estimate, each with :data:`MACHINE_CORES` cores.
MACHINES = (1, 10, 100)
MACHINE_CORES = 16
MILLION = 1_000_000
#: Columns that must agree between executors (the rest are wall times).
COMPARED = ("shot_id", "status", "error_type", "binding_joint", "motion_time", "check_ok")


def shot_set(count: int) -> sweeps.ShotSet:
    """``count`` seeded random Sawyer shots over the default table area, 0.3-1.0 m/s."""
    return sweeps.ShotSet(samples=count, seed=7, headings=(-30.0, 60.0), speeds=(0.3, 1.0))


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _timed(run: Callable[[], list[dict[str, object]]]) -> tuple[float, list[dict[str, object]]]:
    start = time.perf_counter()
    rows = run()
    return time.perf_counter() - start, rows


def _table(rows: list[dict[str, object]]) -> list[tuple[object, ...]]:
    """The compared columns, times to 1 ns: Dask workers run one BLAS thread each
    (``OMP_NUM_THREADS=1``), which moves an optimal-control time in its last digits."""
    return [
        tuple(round(v, 9) if isinstance(v, float) else v for v in (row[n] for n in COMPARED))
        for row in rows
    ]


def _local_cluster(workers: int) -> Any:
    from distributed import LocalCluster

    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",
    )


def measure(shots: sweeps.ShotSet, planner: str, counts: list[int]) -> dict[str, Any]:
    """Wall times [s] of the serial run and of each executor at each worker count.

    Raises:
        RuntimeError: An executor's table differs from the serial one.
    """
    run = sweeps.run
    serial, reference = _timed(lambda: run(shots, planner, workers=0, progress=False))
    found: dict[str, Any] = {"serial": serial, "plan_time": _plan_time(reference), "runs": []}
    for workers in counts:
        wall, rows = _timed(lambda w=workers: run(shots, planner, workers=w, progress=False))
        _same(rows, reference, f"local processes x{workers}")
        found["runs"].append(("local processes", workers, wall))
        with _local_cluster(workers) as cluster:
            run(shots.shots()[:workers], planner, scheduler=cluster, progress=False)  # warm up
            wall, rows = _timed(lambda c=cluster: run(shots, planner, scheduler=c, progress=False))
        _same(rows, reference, f"Dask x{workers}")
        found["runs"].append(("Dask", workers, wall))
        print(f"{workers} workers done", file=sys.stderr)
    return found


def _plan_time(rows: list[dict[str, object]]) -> float:
    """Mean plan time per shot in the serial run [s]."""
    return sum(float(str(row["plan_time"])) for row in rows) / len(rows)


def _same(rows: list[dict[str, object]], reference: list[dict[str, object]], label: str) -> None:
    if _table(rows) != _table(reference):
        raise RuntimeError(f"{label} gave another table than the serial run")


def report(found: dict[str, Any], shots: int, planner: str, command: str) -> list[str]:
    """The Markdown report of :func:`measure`'s figures."""
    serial = found["serial"]
    per_shot = serial / shots
    lines = [
        "# Sweeps: shots per second against workers",
        "",
        f"Command: `{command}` ({shots} random Sawyer pool shots, planner `{planner}`, "
        f"{_cores()} cores; every run gave the serial table, times to 1 ns).",
        "",
        "## Throughput",
        "",
        "| executor | workers | wall [s] | shots/s | parallel efficiency |",
        "|---|---|---|---|---|",
        f"| serial (this process) | 0 | {serial:.2f} | {shots / serial:.2f} | 1.00 |",
    ]
    walls = {}
    for executor, workers, wall in found["runs"]:
        walls[executor, workers] = wall
        efficiency = serial / (workers * wall)
        lines.append(
            f"| {executor} | {workers} | {wall:.2f} | {shots / wall:.2f} | {efficiency:.2f} |"
        )
    lines += ["", "## Dask against local processes", ""]
    lines += ["| workers | overhead per shot [ms] | share of a shot's plan time |", "|---|---|---|"]
    for workers in sorted({w for _, w, _ in found["runs"]}):
        extra = (walls["Dask", workers] - walls["local processes", workers]) / shots
        lines.append(f"| {workers} | {extra * 1e3:+.1f} | {extra / per_shot:+.1%} |")
    best = (
        max(serial / (w * wall) for _, w, wall in found["runs"] if w > 1)
        if any(w > 1 for _, w, _ in found["runs"])
        else 1.0
    )
    lines += [
        "",
        "## A million shots",
        "",
        f"From the serial cost of {per_shot:.3f} s per shot (mean plan time "
        f"{found['plan_time']:.3f} s) and the best measured efficiency {best:.2f}, on "
        f"machines of {MACHINE_CORES} cores:",
        "",
        "| machines | cores | hours |",
        "|---|---|---|",
    ]
    for machines in MACHINES:
        cores = machines * MACHINE_CORES
        hours = MILLION * per_shot / (cores * best) / 3600.0
        lines.append(f"| {machines} | {cores} | {hours:.1f} |")
    return lines


def _arguments(argv: list[str] | None) -> argparse.Namespace:
    def extra(parser: argparse.ArgumentParser) -> None:
        parser.add_argument("--planner", default=None, help=f"pool-shot planner ({PLANNER})")

    args = shot_arguments(
        argv, __doc__, default=SHOTS, quick=QUICK_SHOTS, out=RESULTS / "sweep.md", extra=extra
    )
    if args.planner is None:
        args.planner = QUICK_PLANNER if args.quick else PLANNER
    return args


def _command(args: argparse.Namespace) -> str:
    if args.quick:
        return "python benchmarks/sweep.py --quick"
    words = ["python benchmarks/sweep.py"]
    if args.shots != SHOTS:
        words.append(f"--shots {args.shots}")
    if args.planner != PLANNER:
        words.append(f"--planner {args.planner}")
    return " ".join(words)


def main(argv: list[str] | None = None) -> int:
    args = _arguments(argv)
    counts = sorted({1, 2, _cores()})
    found = measure(shot_set(args.shots), args.planner, counts)
    write_report(report(found, args.shots, args.planner, _command(args)), args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
