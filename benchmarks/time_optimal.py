"""Time-optimal profiles: wrapper overhead and motion durations, side by side in one run.

1. Wall time per plan of optraj's Toppra and Ruckig wrappers against calling toppra and ruckig
   directly on the same cases (median over the cases, ratio wrapper / direct). Goals: <= 1.1x
   for TOPPRA, <= 1.5x for Ruckig.
2. Motion duration of cubic, LSPB, TOPPRA and Ruckig for the same random rest-to-rest moves of
   Sawyer, youBot and Panda, relative to ``planners.lower_bound`` (the time no trajectory
   can beat under the joint velocity, acceleration and jerk limits).

Writes ``benchmarks/results/time_optimal.md`` and prints it.

Usage: ``python benchmarks/time_optimal.py [--moves 50] [--repeats 5] [--quick]``
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import ruckig
import toppra
import toppra.algorithm
import toppra.constraint

from benchmarking import progress, write_report
from optraj import planners, problems, robots
from optraj.errors import MissingDependencyError, OptrajError
from optraj.planners.time_optimal.lower_bound import lower_bound

RESULTS = Path(__file__).resolve().parent / "results"


def timed(call: Callable[[], object], repeats: int) -> float:
    """Best-of-``repeats`` wall time of ``call`` [s] (the least disturbed run)."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def raw_toppra(waypoints: np.ndarray, limits: robots.JointLimits, gridpoints: int) -> object:
    """TOPPRA called directly: spline path, velocity and acceleration constraints."""
    ss = np.linspace(0.0, 1.0, len(waypoints))
    path = toppra.SplineInterpolator(ss, waypoints)
    velocity = toppra.constraint.JointVelocityConstraint(
        np.column_stack([-limits.velocity, limits.velocity])
    )
    acceleration = toppra.constraint.JointAccelerationConstraint(
        np.column_stack([-limits.acceleration, limits.acceleration])
    )
    grid = np.linspace(0.0, 1.0, gridpoints + 1)
    instance = toppra.algorithm.TOPPRA(
        [velocity, acceleration], path, gridpoints=grid, parametrizer="ParametrizeConstAccel"
    )
    return instance.compute_trajectory(0.0, 0.0)


def raw_ruckig(
    q0: np.ndarray,
    q1: np.ndarray,
    limits: robots.JointLimits,
    qd0: np.ndarray | None = None,
    qd1: np.ndarray | None = None,
) -> object:
    """Ruckig called directly, rest to rest or between moving states."""
    n = len(q0)
    inp = ruckig.InputParameter(n)
    inp.current_position = q0
    inp.target_position = q1
    if qd0 is not None and qd1 is not None:
        inp.current_velocity = qd0
        inp.target_velocity = qd1
    inp.max_velocity = limits.velocity
    inp.max_acceleration = limits.acceleration
    inp.max_jerk = limits.jerk
    traj = ruckig.Trajectory(n)
    ruckig.Ruckig(n).calculate(inp, traj)
    return traj


def overhead(repeats: int, cases: int) -> list[str]:
    """Wrapper vs direct call, median time per plan and ratio."""
    robot = robots.load("sawyer")
    rng = np.random.default_rng(2026)
    gridpoints = 100
    rows = []
    timings: dict[str, list[float]] = {
        "toppra": [],
        "toppra direct": [],
        "ruckig": [],
        "ruckig direct": [],
        "ruckig, polynomials built": [],
        "ruckig, moving states": [],
        "ruckig direct, moving states": [],
    }
    for k in range(cases):
        waypoints = robot.random_configurations(5, rng)
        problem = problems.Waypoints(robot, waypoints)
        wrapper = planners.Toppra(gridpoints=gridpoints)
        timings["toppra"].append(timed(lambda: wrapper.plan(problem), repeats))  # noqa: B023
        timings["toppra direct"].append(
            timed(lambda: raw_toppra(waypoints, robot.limits, gridpoints), repeats)  # noqa: B023
        )
        q0, q1 = waypoints[0], waypoints[1]
        move = problems.PointToPoint(robot, q0, q1)
        timings["ruckig"].append(timed(lambda: planners.Ruckig().plan(move), repeats))  # noqa: B023
        timings["ruckig direct"].append(
            timed(lambda: raw_ruckig(q0, q1, robot.limits), repeats)  # noqa: B023
        )
        timings["ruckig, polynomials built"].append(
            timed(lambda: planners.Ruckig().plan(move).coefficients, repeats)  # noqa: B023
        )
        # Moving at a fifth of the speed limits at both ends: positions are then checked.
        qd0, qd1 = 0.2 * robot.limits.velocity * rng.choice([-1.0, 1.0], size=(2, robot.dof))
        moving = problems.PointToPoint(robot, q0, q1, qd_start=qd0, qd_goal=qd1)
        try:
            planners.Ruckig().plan(moving)
        except OptrajError:  # e.g. a joint that would have to overshoot a position limit
            pass
        else:
            timings["ruckig, moving states"].append(
                timed(lambda: planners.Ruckig().plan(moving), repeats)  # noqa: B023
            )
            timings["ruckig direct, moving states"].append(
                timed(lambda: raw_ruckig(q0, q1, robot.limits, qd0, qd1), repeats)  # noqa: B023
            )
        progress(k + 1, cases, "wrapper overhead")
    for name, baseline, goal in (
        ("toppra", "toppra direct", 1.1),
        ("ruckig", "ruckig direct", 1.5),
        ("ruckig, polynomials built", "ruckig direct", None),
        ("ruckig, moving states", "ruckig direct, moving states", None),
    ):
        if not timings[name]:
            continue
        ours = statistics.median(timings[name])
        direct = statistics.median(timings[baseline])
        ratio = ours / direct
        target = "-" if goal is None else f"<= {goal}x ({'meets' if ratio <= goal else 'misses'})"
        rows.append(f"| {name} | {ours * 1e6:.1f} | {direct * 1e6:.1f} | {ratio:.2f}x | {target} |")
    return rows


def durations(moves: int) -> list[str]:
    """Durations of the profiles relative to the lower bound, per robot."""
    names = ["sawyer", "youbot", "panda"]
    profiles: dict[str, Callable[[problems.PointToPoint], planners.Trajectory]] = {
        "cubic": planners.Cubic().plan,
        "lspb": planners.LSPB().plan,
        "toppra": planners.Toppra().plan,
        "ruckig": planners.Ruckig().plan,
    }
    rows = []
    for name in names:
        try:
            robot = robots.load(name)
        except MissingDependencyError as exc:
            rows.append(f"| {name} | skipped: {exc} | | | | |")
            continue
        rng = np.random.default_rng(50)
        ratios: dict[str, list[float]] = {key: [] for key in profiles}
        bounds = []
        for k in range(moves):
            q0, q1 = robot.random_configurations(2, rng)
            problem = problems.PointToPoint(robot, q0, q1)
            bound = lower_bound(problem)
            bounds.append(bound)
            for key, plan in profiles.items():
                ratios[key].append(plan(problem).duration / bound)
            progress(k + 1, moves, f"durations {name}")
        cells = " | ".join(f"{statistics.median(ratios[key]):.3f}" for key in profiles)
        rows.append(f"| {name} | {statistics.median(bounds):.3f} | {cells} |")
    return rows


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the Markdown table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=50, help="random moves per robot")
    parser.add_argument("--repeats", type=int, default=5, help="timing repeats per case")
    parser.add_argument("--cases", type=int, default=20, help="cases for the overhead timing")
    parser.add_argument("--quick", action="store_true", help="a few cases only (for CI)")
    parser.add_argument("--out", type=Path, default=None, help="Markdown file to write")
    args = parser.parse_args(argv)
    if args.quick:
        args.moves, args.repeats, args.cases = 3, 1, 2
    lines = [
        "# Time-optimal profiles",
        "",
        f"Command: `python benchmarks/time_optimal.py --moves {args.moves} "
        f"--repeats {args.repeats} --cases {args.cases}`",
        "",
        "## Wrapper overhead (Sawyer, 5-waypoint paths for TOPPRA with 100 gridpoints; "
        "rest-to-rest moves for Ruckig)",
        "",
        "| planner | optraj [us] | direct [us] | ratio | goal |",
        "|---|---|---|---|---|",
        *overhead(args.repeats, args.cases),
        "",
        "Median over the cases of the best of the repeats. The wrappers include validation,",
        "the exact check of every limit and a `planners.Trajectory`. Ruckig's trajectory",
        "builds its polynomials on first use (`Trajectory.deferred`): the last row times a",
        "plan and that first use together. From rest to rest a joint stays between its start",
        "and its target, so positions need no check until then; moves between moving states",
        "(the fourth row, each joint at a fifth of its speed limit at both ends) are checked",
        "for position limits when planned, which Ruckig's own `position_extrema` cannot do",
        "(it misses extrema inside constant-acceleration phases, pantor/ruckig#215).",
        "",
        f"## Durations relative to the lower bound ({args.moves} random rest-to-rest moves, "
        "median)",
        "",
        "| robot | lower bound [s] | cubic | LSPB | TOPPRA | Ruckig |",
        "|---|---|---|---|---|---|",
        *durations(args.moves),
        "",
        "Ratios are duration / lower bound. The lower bound is the slowest joint's single-axis",
        "time-optimal move under its velocity, acceleration and jerk limits; Ruckig is",
        "time-optimal under all three and sits on it. Cubic, LSPB and TOPPRA ignore the jerk",
        "limit (their jerk is unbounded at blends), so they can come in slightly under it.",
    ]
    write_report(lines, args.out if args.out is not None else RESULTS / "time_optimal.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
