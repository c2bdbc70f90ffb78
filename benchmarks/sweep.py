"""Sweep throughput: shots per second against workers, in local processes and on Dask.

One seeded set of random Sawyer pool shots is planned serially in this process, then in
local processes and on a Dask ``LocalCluster`` on loopback with 1, 2 and all of the
machine's cores as workers; every run must give the serial table (statuses, motion times,
binding joints). Reported, as ratios of the same run:

* parallel efficiency: the faster one-worker wall time of the two executors / (workers x
  the wall time), target >= 0.85 at 2 workers on 2 cores; local processes pay their start (spawn,
  imports) in every run, the Dask cluster is started and its imports done once, as a
  user's cluster is; every worker compiles its own solvers over its first shots;
* Dask's overhead per shot against local processes at the same workers, as a share of one
  shot's wall time on one local worker (target <= 5 %);
* what a map of a million shots would take on N machines, from the measured cost per shot.

It then draws the map of the README, ``sweep_map.png`` beside the table: the fastest cue
speed the velocity limits allow over the table for three headings (a grid sweep in local
processes, planner ``ruckig`` choosing its contact).

By default it measures ruckig on 384 shots and optimal control on 128.

Usage: ``python benchmarks/sweep.py [--quick] [--planner NAME] [--shots N] [--out PATH]``
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

from benchmarking import write_report
from optraj import sweeps

RESULTS = Path(__file__).resolve().parent / "results"
#: (planner, random shots) of the full run: a fast planner on a long sweep, and optimal
#: control, whose workers each compile their solvers, on a shorter one.
CASES = (("ruckig", 384), ("optimal-control", 128))
#: Shots and planner of ``--quick`` (for CI).
QUICK_SHOTS = 8
QUICK_PLANNER = "ruckig"
#: Machines of the million-shot estimate, each with :data:`MACHINE_CORES` cores.
MACHINES = (1, 10, 100)
MACHINE_CORES = 16
MILLION = 1_000_000
#: The map's grid: ball positions along x and y, headings [deg], cue speed [m/s].
MAP_GRID = (12, 10)
QUICK_MAP_GRID = (2, 2)
MAP_HEADINGS = (0.0, 45.0, 90.0)
MAP_SPEED = 0.5
#: Columns that must agree between executors (the rest are wall times).
COMPARED = ("shot_id", "status", "error_type", "binding_joint", "motion_time", "check_ok")


def shot_set(count: int, seed: int = 7) -> list[sweeps.Shot]:
    """``count`` seeded random Sawyer shots over the default table area, 0.3-1.0 m/s."""
    shots = sweeps.ShotSet(samples=count, seed=seed, headings=(-30.0, 60.0), speeds=(0.3, 1.0))
    return list(shots)


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


class Run(NamedTuple):
    """One executor at one worker count: wall time of the sweep and its fixed start [s]."""

    executor: str
    workers: int
    wall: float
    start: float


def measure(shots: list[sweeps.Shot], planner: str, counts: list[int]) -> dict[str, Any]:
    """Wall times [s] of the serial run and of each executor at each worker count.

    An executor's start is the wall time of a sweep of one shot per worker, less one mean
    shot: for local processes, the spawn and imports paid by every sweep; for Dask, what a
    sweep costs on a cluster already warm.

    Raises:
        RuntimeError: An executor's table differs from the serial one.
    """
    run = sweeps.run
    serial, reference = _timed(lambda: run(shots, planner, workers=0, progress=False))
    shot = _plan_time(reference)
    found: dict[str, Any] = {"serial": serial, "plan_time": shot, "runs": []}
    few = shot_set(max(counts), seed=8)
    for workers in counts:
        small, _ = _timed(lambda w=workers: run(few[:w], planner, workers=w, progress=False))
        wall, rows = _timed(lambda w=workers: run(shots, planner, workers=w, progress=False))
        _same(rows, reference, f"local processes x{workers}")
        found["runs"].append(Run("local processes", workers, wall, max(0.0, small - shot)))
        with _local_cluster(workers) as cluster:
            run(few[:workers], planner, scheduler=cluster, progress=False)  # imports, once
            small, _ = _timed(lambda c=cluster, w=workers: run(few[:w], planner, scheduler=c))
            wall, rows = _timed(lambda c=cluster: run(shots, planner, scheduler=c, progress=False))
        _same(rows, reference, f"Dask x{workers}")
        found["runs"].append(Run("Dask", workers, wall, max(0.0, small - shot)))
        print(f"{workers} workers done", file=sys.stderr)
    return found


def _plan_time(rows: list[dict[str, object]]) -> float:
    """Mean plan time per shot in the serial run [s]."""
    return sum(float(str(row["plan_time"])) for row in rows) / len(rows)


def _same(rows: list[dict[str, object]], reference: list[dict[str, object]], label: str) -> None:
    if _table(rows) != _table(reference):
        raise RuntimeError(f"{label} gave another table than the serial run")


def report(cases: list[tuple[str, int, dict[str, Any]]], command: str) -> list[str]:
    """The Markdown report of :func:`measure`'s figures, one block of rows per planner."""
    lines = [
        "# Sweeps: shots per second against workers",
        "",
        f"Command: `{command}` (random Sawyer pool shots, {_cores()} cores; every run gave "
        "the serial table, times to 1 ns). Speed-up is the faster one-worker wall time of the "
        "two executors / the wall time; parallel efficiency is speed-up / workers; start is "
        "the wall time of a sweep of one shot per worker, less a shot (spawn and imports "
        "for local processes; a warm Dask cluster has none). Each optimal-control worker "
        "also compiles its own solvers over its first shots.",
        "",
        "## Throughput",
        "",
        "| planner | shots | executor | workers | wall [s] | shots/s | speed-up "
        "| parallel efficiency | start [s] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for planner, shots, found in cases:
        by = {(r.executor, r.workers): r for r in found["runs"]}
        serial = found["serial"]
        lines.append(
            f"| {planner} | {shots} | serial (this process) | 0 | {serial:.2f} | "
            f"{shots / serial:.2f} | - | - | - |"
        )
        one = min(by[name, 1].wall for name in ("local processes", "Dask"))
        for r in found["runs"]:
            lines.append(
                f"| {planner} | {shots} | {r.executor} | {r.workers} | {r.wall:.2f} | "
                f"{shots / r.wall:.2f} | {one / r.wall:.2f} | "
                f"{one / (r.workers * r.wall):.2f} | {r.start:.2f} |"
            )
    lines += [
        "",
        "## Dask against local processes",
        "",
        "(Dask wall - processes wall) / shots, and as a share of one shot's wall time with "
        "one local worker.",
        "",
        "| planner | workers | overhead per shot [ms] | share of a shot |",
        "|---|---|---|---|",
    ]
    estimates = []
    for planner, shots, found in cases:
        by = {(r.executor, r.workers): r for r in found["runs"]}
        per_shot = by["local processes", 1].wall / shots
        for workers in sorted({r.workers for r in found["runs"]}):
            extra = (by["Dask", workers].wall - by["local processes", workers].wall) / shots
            lines.append(
                f"| {planner} | {workers} | {extra * 1e3:+.1f} | {extra / per_shot:+.1%} |"
            )
        widest = max(r.workers for r in found["runs"])
        one = min(by[name, 1].wall for name in ("local processes", "Dask"))
        best = max(one / (widest * by[name, widest].wall) for name in ("local processes", "Dask"))
        estimates.append((planner, per_shot, best))
    lines += [
        "",
        "## A million shots",
        "",
        "From a planner's wall time a shot on one worker and its best parallel efficiency at "
        f"the most workers measured, on machines of {MACHINE_CORES} cores with one worker a "
        "core (conservative: a worker's start and solver compilation are paid once, not per "
        "shot); hours:",
        "",
        "| machines | cores | "
        + " | ".join(
            f"{planner} ({per_shot:.3f} s a shot, efficiency {best:.2f})"
            for planner, per_shot, best in estimates
        )
        + " |",
        "|---|---|" + "---|" * len(estimates),
    ]
    for machines in MACHINES:
        cores = machines * MACHINE_CORES
        hours = [MILLION * per_shot / (cores * best) / 3600.0 for _, per_shot, best in estimates]
        lines.append(f"| {machines} | {cores} | " + " | ".join(f"{h:.2f}" for h in hours) + " |")
    return lines


def map_shots(quick: bool) -> sweeps.ShotSet:
    """The map's shots: a grid over the table for each heading, at :data:`MAP_SPEED`."""
    return sweeps.ShotSet(
        x=(0.55, 0.95),
        y=(-0.3, 0.45),
        grid=QUICK_MAP_GRID if quick else MAP_GRID,
        headings=MAP_HEADINGS[:1] if quick else MAP_HEADINGS,
        speeds=(MAP_SPEED,),
    )


def draw_map(quick: bool, image: Path) -> dict[str, int]:
    """Sweep :func:`map_shots`, save the max-speed heat map to ``image``; status counts."""
    import matplotlib

    matplotlib.use("Agg")
    options = {"contact": "choose"}
    rows = sweeps.run(map_shots(quick), "ruckig", options=options, progress=False)
    figure = sweeps.plot_max_speed(rows)
    image.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(image, dpi=100)
    counts: dict[str, int] = {}
    for row in rows:
        counts[str(row["status"])] = counts.get(str(row["status"]), 0) + 1
    return counts


def _arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help=f"{QUICK_SHOTS} shots (for CI)")
    parser.add_argument("--planner", help="one pool-shot planner instead of the default cases")
    parser.add_argument("--shots", type=int, help="random shots of each planner")
    parser.add_argument("--out", type=Path, default=RESULTS / "sweep.md", help="Markdown file")
    args = parser.parse_args(argv)
    if args.shots is not None and args.shots < 1:
        parser.error(f"--shots must be >= 1, got {args.shots}")
    if args.quick:
        args.cases = [(QUICK_PLANNER, QUICK_SHOTS)]
    elif args.planner is not None:
        args.cases = [(args.planner, args.shots or dict(CASES).get(args.planner, 128))]
    else:
        args.cases = [(name, args.shots or count) for name, count in CASES]
    return args


def _command(args: argparse.Namespace) -> str:
    if args.quick:
        return "python benchmarks/sweep.py --quick"
    words = ["python benchmarks/sweep.py"]
    if args.planner is not None:
        words.append(f"--planner {args.planner}")
    if args.shots is not None:
        words.append(f"--shots {args.shots}")
    return " ".join(words)


def main(argv: list[str] | None = None) -> int:
    args = _arguments(argv)
    counts = sorted({1, 2, _cores()})
    cases = []
    for planner, shots in args.cases:
        cases.append((planner, shots, measure(shot_set(shots), planner, counts)))
    lines = report(cases, _command(args))
    image = args.out.parent / "sweep_map.png"
    made = draw_map(args.quick, image)
    shown = ", ".join(f"{count} {status}" for status, count in sorted(made.items()))
    lines += [
        "",
        "## Map",
        "",
        f"`{image.name}`: {sum(made.values())} shots at {MAP_SPEED:g} m/s ({shown}); the "
        "colour is the fastest cue speed the velocity limits allow at the chosen contact.",
    ]
    write_report(lines, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
