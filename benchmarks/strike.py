"""Pool strikes on Sawyer: every strike planner on the same seeded random shots, by the checker.

For each planner: success rate (planned, and the checker passes every joint limit but torque
- position, velocity, acceleration, jerk - and every task finding: start and end at rest,
the strike window, position, speed, axis and contact), median motion time, its ratio to the
cubic strike's on the same shot (the profiles start from the contact configuration that
OptimalControl chooses), the peak joint velocity, acceleration and jerk as a fraction
of their limits (worst joint, from the checker), the strike-line position and speed errors
(from the checker) and the planning wall time. A planner raising an ``OptrajError`` fails the
shot; the error classes are tallied.

Then OptimalControl's solve times (cold, first plan, warm, with torque rows, against the
grid) and its results on the same balls at strike speeds from 0.03 to 1.5 m/s.

Writes ``benchmarks/results/strike.md`` (or ``--out``) and prints it.

Usage: ``python benchmarks/strike.py [--shots 100] [--quick] [--out PATH]``
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import statistics
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

from benchmarking import SEED, SPEED, pool_shots, progress, shot_arguments, write_report
from optraj import problems
from optraj.errors import CONTACT_CHOICE, WINDOW_CHECK, InfeasibleError, OptrajError
from optraj.planners import registry
from optraj.planners.checker import Report, check
from optraj.planners.ocp.building import forget_compiled
from optraj.planners.ocp.optimal_control import OptimalControl

RESULTS = Path(__file__).resolve().parent / "results"

QUANTITIES = ("position", "velocity", "acceleration", "jerk")
REFERENCE = "cubic strike"  # the row motion times are compared with
#: The profile rows start from the contact configuration OptimalControl chooses, so that
#: every row but the pull-back shot's compares profiles on the same IK branch (from the
#: problem's own configuration, the one nearest the start, the line itself breaks a limit on
#: most shots).
CONTACT = "choose"
#: Row labels of the registry's pool-shot planners; a planner not named here is labelled
#: with its own ``name``.
LABELS = {
    "pull-back": "pull-back + line",
    "cubic": "cubic strike",
    "quintic": "quintic strike",
    "lspb": "lspb strike",
    "toppra": "toppra strike",
    "ruckig": "ruckig strike",
}
TIMED_SHOTS = 40  # shots of the cold, first-plan and warm rows (p95 is not their maximum)
TORQUE_SHOTS = 10  # shots of the torque rows (each takes rounds of solves)
GRID_SHOTS = 5  # shots timed at each grid size (medians)
WEAK_SHOULDER = 0.1  # right_j0's effort limit in the binding-torque runs, of its rating [-]
#: Strike speeds of the speed table [m/s]: slow strikes (long windows) up to 1.5 m/s, which
#: the velocity limits of many contacts do not allow.
SPEEDS = (0.03, 0.1, 0.3, 1.0, 1.5)
QUICK_SPEEDS = (0.1, 1.0)
SPEED_SHOTS = 10  # balls of the speed table, each struck at every speed
#: Torque runs of the solve-time table: (row label, OptimalControl options, weak shoulder).
TORQUE_RUNS: tuple[tuple[str, dict[str, Any], bool], ...] = (
    ("torque rows, linear", {"torque": True}, False),
    ("torque rows, RNEA", {"torque": True, "torque_rows": "rnea"}, False),
    ("torque binding, linear", {}, True),
)


def planners_to_compare() -> list[tuple[str, Any]]:
    """The (row label, planner) pairs of the table, in row order: every pool-shot planner of
    the registry, those that take a contact choosing it (:data:`CONTACT`)."""
    pairs: list[tuple[str, Any]] = []
    for name in registry.planner_names("pool-shot"):
        settings = {"contact": CONTACT} if "contact" in registry.options("pool-shot", name) else {}
        planner = registry.make_planner("pool-shot", name, **settings)
        pairs.append((LABELS.get(name, planner.name), planner))
    return pairs


class Tally:
    """What one planner did over the shots (medians over the planned shots).

    A plain class, not a dataclass: the tests load this script without registering it in
    ``sys.modules``, which dataclasses need.
    """

    def __init__(self) -> None:
        self.successes = 0
        self.errors: Counter[str] = Counter()
        self.failed_findings: Counter[str] = Counter()
        self.durations: dict[int, float] = {}  # shot index -> motion time [s]
        self.velocity: list[float] = []  # peak / limit, worst joint [-]
        self.acceleration: list[float] = []
        self.jerk: list[float] = []
        self.position_error: list[float] = []  # [m]
        self.speed_error: list[float] = []  # [-]
        self.wall: list[float] = []  # [s]

    def record(self, index: int, duration: float, report: Report, wall: float) -> None:
        """One planned shot."""
        self.durations[index] = duration
        self.wall.append(wall)
        self.velocity.append(report["velocity"].ratio)
        self.acceleration.append(report["acceleration"].ratio)
        self.jerk.append(report["jerk"].ratio)
        self.position_error.append(report["strike position"].value)
        self.speed_error.append(report["strike speed"].value)
        if report.ok:
            self.successes += 1
        self.failed_findings.update(finding.name for finding in report.violations)


def run(problems_: list[problems.PoolStrike], pairs: list[tuple[str, Any]]) -> dict[str, Tally]:
    """Plan and check every shot with every planner."""
    tallies = {label: Tally() for label, _ in pairs}
    total, done = len(problems_) * len(pairs), 0
    for index, problem in enumerate(problems_):
        for label, planner in pairs:
            tally = tallies[label]
            started = time.perf_counter()
            try:
                traj = planner.plan(problem)
            except OptrajError as exc:
                tally.errors[type(exc).__name__] += 1
            else:
                wall = time.perf_counter() - started
                report = check(traj, problem, quantities=QUANTITIES)
                tally.record(index, traj.duration, report, wall)
            done += 1
            progress(done, total, f"shot {index + 1}: {label}")
    return tallies


def _median(values: list[float]) -> float:
    return statistics.median(values) if values else math.nan


def _cell(value: float, digits: int = 3) -> str:
    if math.isnan(value):
        return "-"
    if math.isinf(value):
        return "inf"
    return f"{value:.{digits}f}"


def _counts(counter: Counter[str]) -> str:
    return ", ".join(f"{name} {count}" for name, count in counter.most_common()) or "-"


def table(tallies: dict[str, Tally], count: int) -> list[str]:
    """The Markdown table, one row per planner."""
    reference = tallies.get(REFERENCE)
    rows = [
        "| planner | success | motion time [s] | vs cubic | peak velocity | peak acceleration "
        "| peak jerk | line position error [mm] | speed error [%] | planning [ms] | errors "
        "| checker failures |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, tally in tallies.items():
        ratios = [
            duration / reference.durations[index]
            for index, duration in tally.durations.items()
            if reference is not None and index in reference.durations
        ]
        cells = [
            f"{tally.successes}/{count} ({100.0 * tally.successes / max(count, 1):.0f} %)",
            _cell(_median(list(tally.durations.values()))),
            _cell(_median(ratios)),
            _cell(_median(tally.velocity)),
            _cell(_median(tally.acceleration)),
            _cell(_median(tally.jerk)),
            _cell(1e3 * _median(tally.position_error), 4),
            _cell(1e2 * _median(tally.speed_error), 4),
            _cell(1e3 * _median(tally.wall), 1),
            _counts(tally.errors),
            _counts(tally.failed_findings),
        ]
        rows.append(f"| {label} | {' | '.join(cells)} |")
    return rows


def _timed(
    planner: OptimalControl, problem: problems.PoolStrike, **kwargs: Any
) -> dict[str, float]:
    """Wall, contact choice, NLP and NLP function evaluation times [ms], iterations, motion
    time [s] and NLP variables of one plan (NaN when it fails)."""
    started = time.perf_counter()
    try:
        traj = planner.plan(problem, **kwargs)
    except OptrajError:
        keys = ("wall", "contact", "nlp", "evaluation", "iterations", "motion", "variables")
        return dict.fromkeys(keys, math.nan)
    wall = 1e3 * (time.perf_counter() - started)
    return {
        "wall": wall,
        "contact": 1e3 * traj.metadata["contact_time"],
        "nlp": 1e3 * traj.metadata["nlp_time"],
        "evaluation": 1e3 * traj.metadata["evaluation_time"],
        "iterations": float(traj.metadata["iterations"]),
        "motion": traj.duration,
        "variables": float(traj.metadata["variables"]),
    }


def _median_or_nan(values: list[float]) -> float:
    return statistics.median(values) if values else math.nan


def _medians(runs: list[dict[str, float]]) -> tuple[str, ...]:
    def med(key: str, digits: int = 1) -> str:
        return _cell(_median_or_nan([r[key] for r in runs if math.isfinite(r[key])]), digits)

    walls = sorted(r["wall"] for r in runs if math.isfinite(r["wall"]))
    p95 = _cell(walls[min(len(walls) - 1, int(0.95 * len(walls)))], 1) if walls else "-"
    return (
        med("wall"),
        p95,
        med("contact"),
        med("nlp"),
        med("evaluation"),
        med("iterations"),
        med("motion", 3),
    )


def weak_shoulder(shot: problems.PoolStrike) -> problems.PoolStrike:
    """The shot with right_j0's effort limit at a tenth of its rating: the torque binds."""
    effort = shot.limits.effort.copy()
    effort[0] *= WEAK_SHOULDER
    return dataclasses.replace(shot, limits=dataclasses.replace(shot.limits, effort=effort))


def _compiled_then_timed(planner: OptimalControl, problem: problems.PoolStrike) -> dict[str, float]:
    """Times ``problem`` after an untimed plan of it has compiled every NLP it needs.

    A plan builds one NLP per grid and per set of torque rows, and compiling one takes far
    longer than solving it; the untimed plan leaves nothing of the problem but the compiled
    solvers behind (no solution is kept), so the timed plan is a cold solve.
    """
    with contextlib.suppress(OptrajError):
        planner.plan(problem)
    return _timed(planner, problem)


def _refused(error: OptrajError) -> bool:
    """Whether a plan's error is the contact choice's or the window check's refusal."""
    return isinstance(error, InfeasibleError) and error.found_by in (CONTACT_CHOICE, WINDOW_CHECK)


def _variant(
    shot: problems.PoolStrike, speed: float | None = None, shift: tuple[float, ...] = (0, 0, 0)
) -> problems.PoolStrike:
    """The shot's heading, its ball moved by ``shift`` [m], struck at ``speed`` (its own when
    None) [m/s]: a new ``problems.sawyer_pool_shot``, so with Sawyer's own limits and the
    default tolerances whatever the shot had."""
    return problems.sawyer_pool_shot(
        float(shot.speed) if speed is None else speed,
        tuple(np.asarray(shot.ball) + np.asarray(shift, dtype=float)),
        heading_deg=float(np.degrees(np.arctan2(shot.direction[1], shot.direction[0]))),
    )


def speed_section(shots: list[problems.PoolStrike], quick: bool = False) -> list[str]:
    """OptimalControl (minimum time) on the same balls at each strike speed of the table."""
    speeds = QUICK_SPEEDS if quick else SPEEDS
    chosen = shots[: 1 if quick else SPEED_SHOTS]
    planner = OptimalControl("time")
    lines = [
        "",
        "## OptimalControl against the strike speed",
        "",
        f"Minimum time, the first {len(chosen)} balls and headings struck at each speed. Each "
        "shot is planned once untimed, which compiles its NLPs, and then once timed; the "
        "timed plan counts. Passed: the checker passes the trajectory (as above). Refused: "
        "an `InfeasibleError` from the contact choice before any NLP (no contact "
        "configuration found reaches the speed within the velocity limits), or after a "
        "solve found the strike infeasible, from the window check (every strike window "
        "tried, with the approach into it and the stop after it, needs more than the "
        "limits; the error names the limit that binds first). Failed: any other "
        "`OptrajError`, or a trajectory the checker fails. Plan times, iterations and "
        "motions are medians over the passed shots; time to an error is the longest timed "
        "plan that raised (refused or failed). Rounds are the solves of a plan: more than one "
        "when the strike grid is refined, or when torque or position rows come in.",
        "",
        "| speed [m/s] | window [s] | passed | refused | failed | median plan [ms] "
        "| max plan [ms] | median iterations | plans of more than one round "
        "| median motion [s] | max time to an error [ms] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for step, speed in enumerate(speeds):
        progress(step, len(speeds), "optimal control against the speed")
        passed: list[tuple[float, float, float, int]] = []
        errors: list[float] = []  # wall times of the timed plans that raised [ms]
        refused = failed = 0
        window = math.nan
        for shot in chosen:
            problem = _variant(shot, speed)
            window = problem.window
            with contextlib.suppress(OptrajError):
                planner.plan(problem)  # untimed: compiles this shot's NLPs
            started = time.perf_counter()
            try:
                traj = planner.plan(problem)
            except OptrajError as exc:
                errors.append(1e3 * (time.perf_counter() - started))
                if _refused(exc):
                    refused += 1
                else:
                    failed += 1
                continue
            wall = 1e3 * (time.perf_counter() - started)
            if not check(traj, problem).ok:
                failed += 1
                continue
            meta = traj.metadata
            passed.append((wall, float(meta["iterations"]), traj.duration, int(meta["rounds"])))
        walls = [p[0] for p in passed]
        lines.append(
            f"| {speed:g} | {window:.3g} | {len(passed)}/{len(chosen)} | {refused} | {failed} "
            f"| {_cell(_median_or_nan(walls), 1)} | {_cell(max(walls, default=math.nan), 1)} "
            f"| {_cell(_median_or_nan([p[1] for p in passed]), 0)} "
            f"| {sum(p[3] > 1 for p in passed)} "
            f"| {_cell(_median_or_nan([p[2] for p in passed]), 3)} "
            f"| {_cell(max(errors, default=math.nan), 1)} |"
        )
    progress(len(speeds), len(speeds), "optimal control against the speed")
    return lines


def extra_sections(shots: list[problems.PoolStrike], quick: bool = False) -> list[str]:
    """OptimalControl's solve times: cold, warm (ball moved 2 cm), torque rows, grid size."""
    count = 1 if quick else min(len(shots), TIMED_SHOTS)
    torque_count = 0 if quick else min(count, TORQUE_SHOTS)
    chosen = shots[:count]
    first: list[dict[str, float]] = []
    cold: list[dict[str, float]] = []
    warm: list[dict[str, float]] = []
    plain = OptimalControl("time")
    torque_runs: dict[str, list[dict[str, float]]] = {label: [] for label, _, _ in TORQUE_RUNS}
    torque_planners = {label: OptimalControl("time", **kwargs) for label, kwargs, _ in TORQUE_RUNS}
    for index, shot in enumerate(chosen):
        progress(index, count, "optimal control extras")
        previous = plain.plan(shot) if math.isfinite(_timed(plain, shot)["wall"]) else None
        if previous is not None:
            # Untimed: compiles the warm-start solver of this grid, as the cold one already is.
            with contextlib.suppress(OptrajError):
                plain.plan(shot, warm_start=previous)
        moved = _variant(shot, shift=(0.0, 0.02, 0.0))
        forget_compiled()  # a first plan in the process: its NLP built and compiled
        first.append(_timed(OptimalControl("time"), moved))
        cold.append(_compiled_then_timed(plain, moved))
        if previous is not None:
            warm.append(_timed(plain, moved, warm_start=previous))
        if index < torque_count:
            for label, _, weak in TORQUE_RUNS:
                torque_runs[label].append(
                    _compiled_then_timed(
                        torque_planners[label], weak_shoulder(moved) if weak else moved
                    )
                )
    progress(count, count, "optimal control extras")
    grid = []
    sizes = (5, 10) if quick else (5, 10, 20, 40)
    grid_shots = chosen[:GRID_SHOTS]
    torque_over = "the first shot" if torque_count == 1 else f"the first {torque_count} shots"
    for step, intervals in enumerate(sizes):
        progress(step, len(sizes), "solve time against the grid")
        planner = OptimalControl("time", intervals=intervals, max_interval=2.0)
        grid.append((intervals, [_compiled_then_timed(planner, s) for s in grid_shots]))
    progress(len(sizes), len(sizes), "solve time against the grid")
    over = f"the first {len(grid_shots)} shots" if len(grid_shots) > 1 else "the first shot"
    lines = [
        "",
        "## OptimalControl solve times",
        "",
        f"Minimum time, {count} shots; cold: the ball moved 2 cm from each shot, solved from "
        "scratch after an untimed plan of the same problem (which compiles every NLP the plan "
        "needs and keeps no solution); first plan: the same problem planned by a new planner, "
        "so the wall time includes building and compiling its NLP; warm: started from the "
        "unmoved shot's solution (primal and dual, and its contact branch when that still has "
        "room; the warm-start solver compiled already). Torque rows at every node from "
        "the start (`torque=True`), linear (the default) or symbolic RNEA, and torque limits "
        f"that bind (right_j0's effort at {WEAK_SHOULDER:g} of its rating, default "
        f'`torque="auto"`): timed like the cold row over {torque_over}; NLP time and '
        "iterations are summed over every round. Wall time includes the contact choice (the "
        "search, or one local IK on the warm start's branch; `contact_time`) and every round; "
        "NLP time is the solver's (`nlp_time`), of which CasADi's evaluations of the NLP's "
        "functions and derivatives are `evaluation_time`: the rest is IPOPT's own work, "
        "mostly its sparse linear algebra. A kept branch may not be the one a cold plan picks "
        "(the one the arm reaches soonest), so warm motions may take longer.",
        "",
        "| run | median wall [ms] | p95 wall [ms] | median contact choice [ms] "
        "| median NLP [ms] | median NLP evaluations [ms] | median iterations "
        "| median motion [s] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    rows = (("cold", cold), ("first plan", first), ("warm", warm), *torque_runs.items())
    for label, runs in rows:
        lines.append(f"| {label} | " + " | ".join(_medians(runs)) + " |")
    lines += [
        "",
        f"Solve time against the grid (intervals per phase; medians over {over}, each after "
        "an untimed plan of it that compiles the grid's solver). NLP per iteration per "
        "variable stays flat when the cost of an iteration grows linearly with the problem.",
        "",
        "| intervals per phase | NLP variables | solved | wall [ms] | NLP [ms] | iterations "
        "| NLP per iteration [ms] | per iteration and variable [us] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for intervals, runs in grid:
        solved = [r for r in runs if math.isfinite(r["wall"])]
        per_iteration = _median_or_nan([r["nlp"] / r["iterations"] for r in solved])
        variables = _median_or_nan([r["variables"] for r in solved])
        lines.append(
            f"| {intervals} | {_cell(variables, 0)} | {len(solved)}/{len(runs)} | "
            f"{_cell(_median_or_nan([r['wall'] for r in solved]), 1)} | "
            f"{_cell(_median_or_nan([r['nlp'] for r in solved]), 1)} | "
            f"{_cell(_median_or_nan([r['iterations'] for r in solved]), 0)} | "
            f"{_cell(per_iteration, 2)} | {_cell(1e3 * per_iteration / variables, 2)} |"
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the Markdown table."""
    args = shot_arguments(argv, __doc__, 100, 4, RESULTS / "strike.md")
    out = args.out
    problems_, redrawn = pool_shots(args.shots)
    pairs = planners_to_compare()
    started = time.perf_counter()
    tallies = run(problems_, pairs)
    elapsed = time.perf_counter() - started
    lines = [
        "# Pool strikes on Sawyer",
        "",
        f"Command: `python benchmarks/strike.py --shots {args.shots}`",
        "",
        f"{args.shots} seeded random shots (seed {SEED}) at {SPEED:g} m/s: ball centre "
        "x in [0.65, 0.85] m, y in [-0.05, 0.3] m, z in [-0.1, 0] m, heading in [-20, 20] deg "
        f"(`problems.sawyer_pool_shot`; {redrawn} draws out of reach were redrawn). "
        f"{elapsed:.0f} s in all.",
        "",
        *table(tallies, args.shots),
        "",
        "Success: planned, and `planners.check` passes the position, velocity, acceleration",
        "and jerk limits and every task finding (rest at both ends; strike window, position,",
        "speed, axis, contact). Every other column is the median over the shots the planner",
        "planned, whether or not they pass: motion time; its ratio to the cubic strike's on",
        "the same shot; the worst joint's peak |velocity|, |acceleration| and |jerk| over its",
        "limit (`inf`: the quantity below it jumps); the largest distance of the cue tip from",
        "its strike schedule and the largest speed error along (or across) the line; the",
        "planning wall time. Errors: the `OptrajError` classes raised; checker failures: how",
        "often each finding failed. The profile rows (cubic to Ruckig) start from the",
        'contact configuration OptimalControl chooses (`contact="choose"`), so that all but',
        "the pull-back shot's compare profiles on one IK branch; the pull-back shot starts from",
        "the problem's own",
        "(the IK solution nearest the start).",
    ]
    lines.extend(extra_sections(problems_, quick=args.quick))
    lines.extend(speed_section(problems_, quick=args.quick))
    write_report(lines, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
