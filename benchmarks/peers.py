"""Ahead of every peer: optraj and its peers timed side by side, interleaved, in one run.

The protocol of issue 35. Panda (7 joints), one BLAS/OpenMP thread, seed 35: 16 random
moves with start and goal in the middle 80 % of each joint's range, boundary velocities up
to a fifth of the speed limits, and two via points per move for the multi-point rows. The
problems are built before the clock starts (building one is its own row). For every move,
the optraj call and the peer call alternate ``--repeats`` times (after one untimed call of
each); a row's time is the median over the moves of each move's median. The ratio is peer
/ optraj (>= 1: optraj is faster), or, for the rows against optraj itself, the quotient the
target names. Strike rows use the pool shots of benchmarks/strike.py (Sawyer); the
DiffIKQP row replays the states of one closed-loop run, step by step.

A peer that is not installed leaves its rows "peer not installed" (optraj is still timed);
a peer that fails on a move says so, and the move is left out of both medians.

Writes the Markdown table to ``--out`` (a fresh folder under the temporary directory when not
given; ``make bench`` writes ``benchmarks/results/peers.md``) and prints it.

Usage: ``python benchmarks/peers.py [--moves 16] [--repeats 5] [--shots 8] [--quick] [--out PATH]``
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import peer_calls as peer
from peer_rows import (
    SEED,
    Moves,
    OcpRows,
    diffik_row,
    profile_rows,
    scaling_rows,
    strike_rows,
    time_optimal_rows,
)
from peer_timing import Row, measure, table

from benchmarking import progress, write_report
from optraj import robots
from optraj.sweeps.processes import THREAD_VARIABLES

#: The moves of ``--quick``: the first two of the protocol's 16 that a 2 s quintic can make
#: within Panda's velocity limits (the others need a joint above its limit in 2 s).
QUICK_MOVES = (4, 5)
QUICK_SHOTS = 2  # the Ruckig strike refuses the first shot: the second gives the row
QUICK_STEPS = 100  # DiffIKQP steps replayed with --quick


def run(args: argparse.Namespace) -> tuple[list[Row], OcpRows]:
    """Every row of the protocol, in table order."""
    robot = robots.load("panda")
    moves = Moves(robot, QUICK_MOVES if args.quick else range(args.moves))
    ocp = OcpRows(robot, moves)
    specs = [
        *scaling_rows(moves),
        *profile_rows(robot, moves),
        *time_optimal_rows(robot, moves),
        *ocp.specs(),
    ]
    total = len(specs) + 3
    rows = []
    for spec in specs:
        progress(len(rows), total, spec.label)
        rows.append(measure(spec, moves.count, args.repeats))
    for spec in strike_rows(args.shots):
        progress(len(rows), total, spec.label)
        rows.append(measure(spec, args.shots, args.repeats))
    progress(len(rows), total, "DiffIKQP step")
    steps = QUICK_STEPS if args.quick else None
    rows.append(diffik_row(robot, moves, args.repeats, steps))
    progress(len(rows), total, "peers")
    return rows, ocp


def report(args: argparse.Namespace, rows: list[Row], ocp: OcpRows, seconds: float) -> list[str]:
    """The Markdown lines of the report."""
    threads = ", ".join(f"{name}={os.environ.get(name, 'unset')}" for name in THREAD_VARIABLES)
    return [
        "# optraj against its peers",
        "",
        f"Command: `{command(args)}`",
        "",
        f"Panda, {args.moves} seeded moves (seed {SEED}), {args.repeats} interleaved repeats "
        f"per move; strike rows: {args.shots} Sawyer pool shots; {threads}. {seconds:.0f} s "
        "in all. Times are medians over the moves of each move's median [us].",
        "",
        *table(rows),
        "",
        "Peers: Robotics Toolbox `jtraj(q0, q1, np.linspace(0, T, 101), qd0, qd1)` at the",
        "planner's duration T, `mtraj(trapezoidal, ...)` at the LSPB's T, `mstraj(points,",
        "dt=0.01, tacc=0.2, qdmax=velocity limits)` through start, two vias and goal; ruckig's",
        "`calculate` with its `InputParameter` built from the arrays; toppra on the same cubic",
        "through the same waypoints (its own spline, or scipy's PCHIP on the moves where",
        "optraj's spline would leave the position limits) on the same grid;",
        "`benchmarks/bare_ocp.py` (a bare CasADi + IPOPT minimum-time transcription, its NLP",
        f"reused) and Drake's `KinematicTrajectoryOptimization` ({peer.DRAKE_CONTROL_POINTS}",
        "control points, one program reused with new start and goal bounds) with IPOPT, for",
        "the same rest-to-rest moves; pink's `solve_ik` with daqp on the tracking benchmark's",
        "task (tool pose and posture), on the states of one DiffIKQP run of the first move.",
        "Strike rows: each shot planned once, then its ball moved 2 cm: warm re-plans it from",
        "that plan, cold plans it from scratch (its NLPs compiled by the untimed call), the",
        'Ruckig strike is the registry\'s pool-shot `ruckig` planner (`contact="choose"`).',
        "Ratios are peer / optraj unless the target names another quotient. Moves: those timed",
        "of those drawn; a move optraj refuses (e.g. a 2 s time scaling that needs a joint",
        "above its velocity limit) or the other side fails on is left out of both columns.",
        "",
        "## Minimum time: IPOPT iterations and motion time",
        "",
        *ocp.table(),
        "",
        "Each solver against the lower bound of the limits it was given: optraj's planner",
        "keeps the jerk limit as well; the bare OCP and Drake's problem have none.",
    ]


def command(args: argparse.Namespace) -> str:
    """The command line that repeats this run."""
    if args.quick:
        return "python benchmarks/peers.py --quick"
    return (
        f"python benchmarks/peers.py --moves {args.moves} --repeats {args.repeats} "
        f"--shots {args.shots}"
    )


def single_threaded() -> bool:
    """Whether every BLAS/OpenMP thread-count variable is 1 in this process."""
    return all(os.environ.get(name) == "1" for name in THREAD_VARIABLES)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark (in a child process with one thread when this one has more)."""
    arguments = list(sys.argv[1:] if argv is None else argv)
    if not single_threaded():
        env = {**os.environ, **dict.fromkeys(THREAD_VARIABLES, "1")}
        child = subprocess.run([sys.executable, __file__, *arguments], env=env, check=False)
        return child.returncode
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=16, help="random moves")
    parser.add_argument("--repeats", type=int, default=5, help="interleaved repeats per move")
    parser.add_argument("--shots", type=int, default=8, help="pool shots of the strike rows")
    parser.add_argument("--quick", action="store_true", help="2 moves, 2 shots, 1 repeat (CI)")
    parser.add_argument("--out", type=Path, default=None, help="Markdown file to write")
    args = parser.parse_args(arguments)
    if args.quick:
        args.moves, args.repeats, args.shots = len(QUICK_MOVES), 1, QUICK_SHOTS
    for name in ("moves", "repeats", "shots"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be >= 1, got {getattr(args, name)}")
    out = args.out or Path(tempfile.mkdtemp(prefix="optraj-peers-")) / "peers.md"
    started = time.perf_counter()
    rows, ocp = run(args)
    write_report(report(args, rows, ocp, time.perf_counter() - started), out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
