"""Where the ball goes: planners x controllers x conditions, judged by the ball in MuJoCo.

Random reachable Sawyer pool shots (benchmarking.pool_shots) at 0.5 and 1.0 m/s and paddle4
strikes, each planned, tracked on physics.MujocoPlant at 1 kHz and judged by
physics.outcome: hit rate, heading and speed errors (median / p95) and the share within
0.5 deg and 2 % of the commanded shot. "plan alone" is the plan replayed by a kinematic tool.

Every plan is replayed alone for all ``--shots``; the minimum-time OCP (the README's tracked
plan) is tracked by every controller in every condition for all of them, the other planners
for the first ``--others`` shots of each speed. The link-mass conditions scale each link's
mass and inertia by a seeded draw from 1 to 1.1 (or 0.9 to 1). Shots run in ``--workers``
processes; the outcome of a shot does not depend on how many.

Writes the table to ``--out`` and, beside it, ``outcome_paths.png`` (balls from above) and
``outcome_heading.png`` (heading-error distribution per controller and condition).

Usage: ``python benchmarks/outcome.py [--shots N] [--others N] [--paddle N] [--workers N]
[--quick] [--out PATH]``
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import multiprocessing
import os
import sys
from collections import defaultdict
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

import numpy as np

from benchmarking import pool_shots, progress, shot_arguments, write_report
from optraj import controllers, physics, planners, problems
from optraj.errors import OptrajError
from optraj.planners.plot import pyplot
from optraj.planners.trajectory import Trajectory
from optraj.robots import Robot

RESULTS = Path(__file__).resolve().parent / "results"
#: Plans use this fraction of the limits, leaving the controllers room (README).
PLAN_MARGIN = 0.8
SPEEDS = (0.5, 1.0)
CONDITIONS = ("nominal", "noise", "latency 2", "masses +10 %", "masses -10 %", "push")
PUSH = 20.0  # [N] down on the tool for 10 ms, 50 ms before the strike window
#: Paddle strikes: ball speed along the paddle normal [m/s].
PADDLE_SPEED = 0.5
#: Default counts: pool shots per speed, shots per speed on which the other planners are
#: tracked too, paddle strikes.
SHOTS = 100
OTHERS = 20
PADDLE = 50
#: Random paddle balls drawn per wanted strike before giving up.
PADDLE_ATTEMPTS = 20
#: The planner every controller tracks for every shot (the others for ``--others`` shots).
PRIMARY = "min-time OCP"
CONTROLLERS = ("PseudoInversePID", "DiffIKQP", "JointPD")
#: Targets of issue 31 for DiffIKQP on the primary plans: share within, by condition.
TARGET_SHARE = {"nominal": 0.99, "noise": 0.99, "latency 2": 0.95, "masses +10 %": 0.95,
                "masses -10 %": 0.95}  # fmt: skip
TARGET_MEDIAN = 0.05  # [deg] DiffIKQP median |heading error|, nominal
TARGET_PADDLE = 0.99
#: A plan alone that touches the ball this long before its strike line [s] hit it on the way.
EARLY = 1e-3

Key = tuple[str, ...]
Note = tuple[str, str, str]


def _planners() -> list[tuple[str, Any, bool]]:
    """(label, planner, plan within PLAN_MARGIN of the limits)."""
    return [
        (PRIMARY, planners.OptimalControl("time"), True),
        ("min-jerk OCP", planners.OptimalControl("jerk"), True),
        ("Ruckig strike", planners.TimeOptimalStrike(), True),
        ("pull-back", planners.PullBackStrike(), False),
    ]


def _controller(label: str, robot: Robot) -> controllers.Controller:
    return {
        "PseudoInversePID": controllers.PseudoInversePID,
        "DiffIKQP": controllers.DiffIKQP,
        "JointPD": controllers.JointPD,
    }[label](robot)


@functools.cache
def _base(count: int) -> list[problems.PoolStrike]:
    return pool_shots(count)[0]


def _slim(outcome: physics.Outcome) -> physics.Outcome:
    """The outcome with its run path thinned (the ball rests until the strike)."""
    path = outcome.path
    return dataclasses.replace(outcome, path=np.concatenate([path[::25], path[-1:]]))


def _run(
    shot: problems.PoolStrike, traj: Trajectory, label: str, condition: str, seed: int
) -> physics.Outcome:
    options: dict[str, Any] = {}
    scene_options: dict[str, Any] = {}
    if condition == "noise":
        options["noise"] = controllers.Noise(seed=seed)
    elif condition == "latency 2":
        options["latency"] = 2
    elif condition.startswith("masses"):
        rng = np.random.default_rng(seed)
        sign = 1.0 if "+" in condition else -1.0
        scene_options["mass_scale"] = 1.0 + sign * rng.uniform(0.0, 0.1, shot.robot.dof)
    elif condition == "push":
        start = traj.phase("strike").t_start - 0.05
        options["disturbance"] = controllers.Impulse(start, [0.0, 0.0, -PUSH], 0.01)
    plant = physics.MujocoPlant(physics.scene_for(shot, **scene_options))
    controller = _controller(label, shot.robot)
    result = controllers.simulate(shot.robot, traj, controller, plant=plant, settle=0.05, **options)
    return _slim(physics.outcome(result, shot))


def pool_case(
    speed: float, index: int, count: int, tracked: tuple[str, ...], conditions: tuple[str, ...]
) -> tuple[list[tuple[Key, physics.Outcome]], list[str]]:
    """One shot at one speed: every planner alone, the ``tracked`` ones by every controller.

    Returns ``([(key, outcome), ...], notes)``: keys are ``(speed, planner, controller or
    "plan alone", condition or "-")``; a note is ``(planner, kind, text)`` with kind
    ``"failed"`` (the plan raised an OptrajError), ``"early"`` (the plan alone touched the ball
    before its strike line) or ``"error"`` (anything else raised: a defect, reported).
    """
    shot = dataclasses.replace(_base(count)[index], speed=speed)
    found: list[tuple[Key, physics.Outcome]] = []
    notes: list[Note] = []
    for name, planner, margin in _planners():
        roomy = shot.robot.limits.scaled(PLAN_MARGIN)
        problem = dataclasses.replace(shot, limits=roomy) if margin else shot
        try:
            traj = planner.plan(problem)
        except OptrajError as exc:
            notes.append((name, "failed", type(exc).__name__))
            continue
        except Exception as exc:  # a defect: reported in the table, the run goes on
            notes.append((name, "error", f"shot {index} at {speed:g} m/s: {_reason(exc)}"))
            continue
        try:
            alone = physics.outcome(physics.replay(physics.scene_for(shot), traj), shot)
            found.append(((f"{speed:g}", name, "plan alone", "-"), _slim(alone)))
            if alone.hit and alone.contact_time < traj.phase("strike").t_start - EARLY:
                notes.append((name, "early", f"shot {index} at {speed:g} m/s"))
            if name not in tracked:
                continue
            for label in CONTROLLERS:
                for condition in conditions:
                    outcome = _run(shot, traj, label, condition, seed=index)
                    found.append(((f"{speed:g}", name, label, condition), outcome))
        except Exception as exc:  # a defect: reported in the table, the run goes on
            notes.append((name, "error", f"shot {index} at {speed:g} m/s: {_reason(exc)}"))
    return found, notes


def _reason(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"[:160]


def paddle_cases(count: int) -> dict[str, list[physics.Outcome]]:
    """``count`` random reachable paddle4 strikes, alone and tracked by every controller."""
    rng = np.random.default_rng(11)
    robot = problems.ece486_paddle_strike().robot
    found: dict[str, list[physics.Outcome]] = defaultdict(list)
    planner = planners.OptimalControl("time")
    made = attempts = 0
    while made < count:
        attempts += 1
        if attempts > PADDLE_ATTEMPTS * count:
            raise RuntimeError(f"only {made} of {count} random paddle strikes planned")
        ball = (rng.uniform(0.5, 1.0), rng.uniform(-0.5, 0.5), rng.uniform(0.1, 0.6))
        try:
            strike = problems.PaddleStrike(robot, ball=ball, speed=PADDLE_SPEED)
            traj = planner.plan(
                dataclasses.replace(strike, limits=robot.limits.scaled(PLAN_MARGIN))
            )
        except OptrajError:
            continue
        made += 1
        alone = physics.outcome(physics.replay(physics.scene_for(strike), traj), strike)
        found["plan alone"].append(_slim(alone))
        for label in CONTROLLERS:
            plant = physics.MujocoPlant(physics.scene_for(strike))
            result = controllers.simulate(
                robot, traj, _controller(label, robot), plant=plant, settle=0.05
            )
            found[label].append(_slim(physics.outcome(result, strike)))
    return dict(found)


def _share(outcomes: list[physics.Outcome]) -> float:
    return sum(o.within for o in outcomes) / max(len(outcomes), 1)


def _row(label: Key, outcomes: list[physics.Outcome]) -> str:
    hits = [o for o in outcomes if o.hit]
    cells = [*label, f"{len(hits)}/{len(outcomes)}"]
    within = sum(o.within for o in outcomes)
    cells.append(f"{within}/{len(outcomes)} ({100 * within / max(len(outcomes), 1):.0f} %)")
    if hits:
        heading = np.abs([o.heading_error for o in hits])
        speed = np.abs([o.speed_error for o in hits]) * 100
        cells.append(f"{np.median(heading):.3f} / {np.percentile(heading, 95):.3f}")
        cells.append(f"{np.median(speed):.2f} / {np.percentile(speed, 95):.2f}")
    else:
        cells += ["- (no hit)", "- (no hit)"]
    return "| " + " | ".join(cells) + " |"


def _targets(
    pool: dict[Key, list[physics.Outcome]],
    paddle: dict[str, list[physics.Outcome]],
    speeds: tuple[float, ...],
    conditions: tuple[str, ...],
    early: dict[str, int],
) -> list[str]:
    """The issue's targets against this run: one row each, met or not."""
    rows: list[tuple[str, str, str, bool | None]] = []
    for name, _, _ in _planners():
        alone = [o for k, items in pool.items() if k[1:3] == (name, "plan alone") for o in items]
        if alone:
            struck = early.get(name, 0)
            note = f" ({struck} knocked the ball before the strike line)" if struck else ""
            share = _share(alone)
            rows.append((f"{name} alone within", "100 %", f"{100 * share:.1f} %{note}",
                         share == 1.0))  # fmt: skip
    for speed in speeds:
        s = f"{speed:g}"
        for condition in conditions:
            qp = pool.get((s, PRIMARY, "DiffIKQP", condition), [])
            pid = pool.get((s, PRIMARY, "PseudoInversePID", condition), [])
            if not qp:
                continue
            need = TARGET_SHARE.get(condition)
            missed = sum(not o.hit for o in qp)
            got = f"{100 * _share(qp):.1f} % ({missed} missed; PID {100 * _share(pid):.1f} %)"
            rows.append((f"DiffIKQP within, {s} m/s, {condition}",
                         f">= {100 * need:.0f} %, no miss" if need else "no miss", got,
                         missed == 0 and (need is None or _share(qp) >= need)))  # fmt: skip
        nominal = pool.get((s, PRIMARY, "DiffIKQP", "nominal"), [])
        if nominal:
            median = float(np.median(np.abs([o.heading_error for o in nominal])))
            rows.append((f"DiffIKQP median heading, {s} m/s, nominal", f"<= {TARGET_MEDIAN} deg",
                         f"{median:.3f} deg", median <= TARGET_MEDIAN))  # fmt: skip
    lower = [
        f"{key[0]} m/s {key[3]}"
        for key, items in pool.items()
        if key[1] == PRIMARY and key[2] == "DiffIKQP"
        and _share(items) < _share(pool.get((key[0], key[1], "PseudoInversePID", key[3]), []))
    ]  # fmt: skip
    rows.append(("DiffIKQP share never below PID's", "in no condition",
                 ", ".join(lower) or "below in none", not lower))  # fmt: skip
    for label, items in paddle.items():
        share = sum(o.hit and abs(o.heading_error) <= physics.HEADING_TOLERANCE for o in items)
        share /= len(items)
        rows.append((f"paddle {label} within 0.5 deg of the normal",
                     f">= {100 * TARGET_PADDLE:.0f} %", f"{100 * share:.1f} %",
                     share >= TARGET_PADDLE))  # fmt: skip
    lines = ["| target | wanted | this run | met |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {'yes' if ok else 'NO'} |" for a, b, c, ok in rows]
    return lines


def draw_plots(
    pool: dict[Key, list[physics.Outcome]],
    speeds: tuple[float, ...],
    conditions: tuple[str, ...],
    folder: Path,
) -> list[Path]:
    """``outcome_paths.png`` and ``outcome_heading.png`` into ``folder``; the paths written.

    A figure without data (no primary plan at the top speed) is left out.
    """
    import matplotlib

    matplotlib.use("Agg")
    plt = pyplot()
    s = f"{max(speeds):g}"
    keys = {label: (s, PRIMARY, label, "-" if label == "plan alone" else "nominal")
            for label in ("plan alone", *CONTROLLERS)}  # fmt: skip
    paths = {label: pool[key] for label, key in keys.items() if pool.get(key)}
    written = []
    if paths:
        figure = physics.plot_ball_paths(paths)
        figure.suptitle(f"Where the balls went: {PRIMARY} plans at {s} m/s, nominal, from above")
        written.append(folder / "outcome_paths.png")
        figure.savefig(written[-1], dpi=100)
        plt.close(figure)
    panels = {}
    for condition in conditions:
        groups = {
            label: [o for v in speeds for o in pool.get((f"{v:g}", PRIMARY, label, condition), [])]
            for label in CONTROLLERS
        }
        if any(groups.values()):
            panels[condition] = {k: v for k, v in groups.items() if v}
    if panels:
        columns = min(len(panels), 3)
        rows = -(-len(panels) // columns)
        figure, axes = plt.subplots(
            rows, columns, figsize=(4.6 * columns, 3.8 * rows), squeeze=False
        )
        for ax, (condition, groups) in zip(axes.flat, panels.items(), strict=False):
            physics.plot_heading_errors(groups, ax=ax, title=condition, legend="inside")
        for ax in list(axes.flat)[len(panels) :]:
            ax.set_visible(False)
        figure.suptitle(f"|heading error| of {PRIMARY} plans tracked on MuJoCo, all speeds")
        figure.tight_layout()
        written.append(folder / "outcome_heading.png")
        figure.savefig(written[-1], dpi=100)
        plt.close(figure)
    return written


def _arguments(argv: list[str] | None) -> argparse.Namespace:
    def extra(parser: argparse.ArgumentParser) -> None:
        parser.add_argument(
            "--others",
            type=int,
            default=None,
            help=f"shots per speed on which the other planners are tracked (default {OTHERS})",
        )
        parser.add_argument("--paddle", type=int, default=None,
                            help=f"paddle strikes (default {PADDLE})")  # fmt: skip
        parser.add_argument("--workers", type=int, default=None,
                            help="processes, 1: in this one (default: the CPUs)")  # fmt: skip

    args = shot_arguments(argv, __doc__, default=SHOTS, quick=1, out=RESULTS / "outcome.md",
                          extra=extra)  # fmt: skip
    # --quick: one shot at 1 m/s, two conditions, one paddle strike, in this process.
    defaults = {"others": 0, "paddle": 1, "workers": 1} if args.quick else {
        "others": OTHERS, "paddle": PADDLE, "workers": _cpus()}  # fmt: skip
    for name, default in defaults.items():
        if getattr(args, name) is None:
            setattr(args, name, default)
        minimum = 1 if name == "workers" else 0
        if getattr(args, name) < minimum:
            raise SystemExit(f"--{name} must be >= {minimum}, got {getattr(args, name)}")
    args.others = min(args.others, args.shots)
    return args


def _cpus() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _command(args: argparse.Namespace) -> str:
    """The command line that reproduces this run."""
    if args.quick:
        return "python benchmarks/outcome.py --quick"
    words = ["python benchmarks/outcome.py", f"--shots {args.shots}"]
    if args.others != min(OTHERS, args.shots):
        words.append(f"--others {args.others}")
    if args.paddle != PADDLE:
        words.append(f"--paddle {args.paddle}")
    return " ".join(words)


Found = tuple[list[tuple[Key, physics.Outcome]], list[Note]]


def _run_cases(
    cases: list[tuple[Any, ...]], paddle_count: int, workers: int
) -> tuple[dict[tuple[float, int], Found], dict[str, list[physics.Outcome]]]:
    """Every pool case and the paddle strikes, in this process or in ``workers`` processes.

    Raises:
        RuntimeError: A worker process died (the cases not yet run are cancelled).
    """
    results: dict[tuple[float, int], Found] = {}
    paddle: dict[str, list[physics.Outcome]] = {}
    total = len(cases) + (1 if paddle_count else 0)
    label = f"outcome: {len(cases)} shots"
    progress(0, total, label)
    count = cases[0][2] if cases else 1
    if workers == 1:
        for done, case in enumerate(cases, 1):
            results[case[:2]] = pool_case(*case)
            progress(done, total, label)
        paddle = paddle_cases(paddle_count) if paddle_count else {}
        return results, paddle
    # Spawned workers (no fork of a process with solver threads); each draws the shots once.
    context = multiprocessing.get_context("spawn")
    executor = ProcessPoolExecutor(
        workers, mp_context=context, initializer=_base, initargs=(count,)
    )
    with executor:
        futures: dict[Future[Any], tuple[float, int] | None] = {}
        if paddle_count:
            futures[executor.submit(paddle_cases, paddle_count)] = None
        futures.update({executor.submit(pool_case, *case): case[:2] for case in cases})
        try:
            for done, future in enumerate(as_completed(futures), 1):
                key = futures[future]
                if key is None:
                    paddle = future.result()
                else:
                    results[key] = future.result()
                progress(done, total, label)
        except BrokenProcessPool as exc:
            executor.shutdown(cancel_futures=True)
            raise RuntimeError(f"a worker process died ({exc}); {len(results)} cases ran") from exc
        except BaseException:
            executor.shutdown(cancel_futures=True)
            raise
    return results, paddle


def main(argv: list[str] | None = None) -> int:
    args = _arguments(argv)
    quick = args.quick
    speeds = SPEEDS[1:] if quick else SPEEDS
    conditions = CONDITIONS[:1] + CONDITIONS[2:3] if quick else CONDITIONS
    everyone = tuple(name for name, _, _ in _planners())
    cases = [
        (speed, index, args.shots, everyone if index < args.others else (PRIMARY,), conditions)
        for speed in speeds
        for index in range(args.shots)
    ]
    results, paddle = _run_cases(cases, args.paddle, args.workers)
    pool: dict[Key, list[physics.Outcome]] = defaultdict(list)
    failed: dict[str, int] = defaultdict(int)
    early: dict[str, int] = defaultdict(int)
    errors: list[str] = []
    for case in cases:  # in shot order, whatever order the workers finished in
        found, notes = results[case[:2]]
        for key, outcome in found:
            pool[key].append(outcome)
        for name, kind, text in notes:
            if kind == "early":
                early[name] += 1
            elif kind == "failed":
                failed[name] += 1
            else:
                errors.append(f"{name}: {text}")
    lines = [
        "# Strike outcome: where the ball goes",
        "",
        f"Command: `{_command(args)}`"
        f" ({args.shots} random Sawyer shots per speed, every plan alone; {PRIMARY} tracked "
        f"on all of them, the other planners on the first {args.others}; plans within "
        f"{PLAN_MARGIN:g} of the limits except the pull-back shot's, MuJoCo plant at 1 kHz).",
        "",
        "## Targets",
        "",
        *_targets(pool, paddle, speeds, conditions, early),
        "",
        "## Every planner, controller and condition",
        "",
        "| speed [m/s] | planner | controller | condition | hit | within 0.5 deg, 2 % | heading "
        "error median / p95 [deg] | speed error median / p95 [%] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    order = {name: k for k, name in enumerate(everyone)}
    for key in sorted(pool, key=lambda k: (k[0], order[k[1]])):
        lines.append(_row(key, pool[key]))
    lines += [
        "",
        "Plans that failed (an OptrajError): "
        + (", ".join(f"{k} {v}" for k, v in failed.items()) or "none"),
        "",
        "Errors (defects; the case's other rows stand): " + ("; ".join(errors) or "none"),
    ]
    if paddle:
        lines += ["", "## Paddle strikes (paddle4, min-time OCP, nominal)", ""]
        lines += [
            "| controller | hit | within 0.5 deg of the normal, 2 % | heading error median / p95 "
            "[deg] | speed error median / p95 [%] |",
            "|---|---|---|---|---|",
        ]
        lines += [_row((name,), outcomes) for name, outcomes in paddle.items()]
    write_report(lines, args.out)
    for path in draw_plots(pool, speeds, conditions, args.out.parent):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
