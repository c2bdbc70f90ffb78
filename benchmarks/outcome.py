"""Where the ball goes: planners x controllers x conditions, judged by the ball in MuJoCo.

Random reachable Sawyer pool shots (benchmarking.pool_shots) at 0.5 and 1.0 m/s and paddle4
strikes, each planned, tracked on physics.MujocoPlant at 1 kHz and judged by
physics.outcome: hit rate, heading and speed errors (median / p95) and the share within
0.5 deg and 2 % of the commanded shot. "plan alone" is the plan replayed by a kinematic tool.

Usage: ``python benchmarks/outcome.py [--shots N] [--quick] [--out PATH]``
"""

from __future__ import annotations

import dataclasses
import sys
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

import controllers
import physics
import planners
import problems
from benchmarking import pool_shots, progress, shot_arguments, write_report
from optraj.errors import OptrajError

RESULTS = Path(__file__).resolve().parent / "results"
#: Plans use this fraction of the limits, leaving the controllers room (README).
PLAN_MARGIN = 0.8
SPEEDS = (0.5, 1.0)
CONDITIONS = ("nominal", "noise", "latency 2", "masses +10 %", "masses -10 %", "push")
PUSH = 20.0  # [N] down on the tool for 10 ms, 50 ms before the strike window
#: Paddle strikes: ball speed along the paddle normal [m/s].
PADDLE_SPEED = 0.5


def _planners() -> list[tuple[str, Any, bool]]:
    """(label, planner, plan within PLAN_MARGIN of the limits)."""
    return [
        ("min-time OCP", planners.OptimalControl("time"), True),
        ("min-jerk OCP", planners.OptimalControl("jerk"), True),
        ("Ruckig strike", planners.TimeOptimalStrike(), True),
        ("seed", planners.SeedStrike(), False),
    ]


def _controllers(robot) -> list[tuple[str, controllers.Controller]]:
    return [
        ("PseudoInversePID", controllers.PseudoInversePID(robot)),
        ("DiffIKQP", controllers.DiffIKQP(robot)),
        ("JointPD", controllers.JointPD(robot)),
    ]


def _run(shot, traj, controller, condition: str, seed: int) -> physics.Outcome:
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
    result = controllers.simulate(shot.robot, traj, controller, plant=plant, settle=0.05, **options)
    return physics.outcome(result, shot)


def _row(label: tuple[str, ...], outcomes: list[physics.Outcome]) -> str:
    hits = [o for o in outcomes if o.hit]
    heading = np.abs([o.heading_error for o in hits]) if hits else np.array([np.nan])
    speed = np.abs([o.speed_error for o in hits]) * 100 if hits else np.array([np.nan])
    within = sum(o.within for o in outcomes)
    cells = [
        *label,
        f"{len(hits)}/{len(outcomes)}",
        f"{within}/{len(outcomes)} ({100 * within / max(len(outcomes), 1):.0f} %)",
        f"{np.median(heading):.3f} / {np.percentile(heading, 95):.3f}",
        f"{np.median(speed):.2f} / {np.percentile(speed, 95):.2f}",
    ]
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> int:
    args = shot_arguments(argv, __doc__, default=10, quick=1, out=RESULTS / "outcome.md")
    quick = args.quick
    speeds = SPEEDS[1:] if quick else SPEEDS
    conditions = CONDITIONS[:1] + CONDITIONS[2:3] if quick else CONDITIONS
    chosen = _planners()[:1] if quick else _planners()
    base, _ = pool_shots(args.shots)
    pool: dict[tuple[str, ...], list[physics.Outcome]] = defaultdict(list)
    failed: dict[str, int] = defaultdict(int)
    total = len(speeds) * len(base)
    done = 0
    for speed in speeds:
        for index, shot0 in enumerate(base):
            progress(done, total, "outcome: pool shots")
            done += 1
            shot = dataclasses.replace(shot0, speed=speed)
            for name, planner, margin in chosen:
                problem = (
                    dataclasses.replace(shot, limits=shot.robot.limits.scaled(PLAN_MARGIN))
                    if margin
                    else shot
                )
                try:
                    traj = planner.plan(problem)
                except OptrajError:
                    failed[name] += 1
                    continue
                alone = physics.outcome(physics.replay(physics.scene_for(shot), traj), shot)
                pool[(f"{speed:g}", name, "plan alone", "-")].append(alone)
                for label, controller in _controllers(shot.robot):
                    for condition in conditions:
                        outcome = _run(shot, traj, controller, condition, seed=index)
                        pool[(f"{speed:g}", name, label, condition)].append(outcome)
    progress(total, total, "outcome: pool shots")
    paddle = _paddle(1 if quick else max(args.shots // 2, 1))
    lines = [
        "# Strike outcome: where the ball goes",
        "",
        f"Command: `python benchmarks/outcome.py{' --quick' if quick else ''}`"
        f" ({args.shots} random Sawyer shots per speed, plans within {PLAN_MARGIN:g} of the "
        "limits except the seed's, MuJoCo plant at 1 kHz).",
        "",
        "| speed [m/s] | planner | controller | condition | hit | within 0.5 deg, 2 % | heading "
        "error median / p95 [deg] | speed error median / p95 [%] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    lines += [_row(key, outcomes) for key, outcomes in pool.items()]
    lines += [
        "",
        "Plans that failed: " + (", ".join(f"{k} {v}" for k, v in failed.items()) or "none"),
    ]
    lines += ["", "## Paddle strikes (paddle4, min-time OCP, nominal)", ""]
    lines += [
        "| controller | hit | within 0.5 deg of the normal, 2 % | heading error median / p95 "
        "[deg] | speed error median / p95 [%] |",
        "|---|---|---|---|---|",
    ]
    lines += [_row((label,), outcomes) for label, outcomes in paddle.items()]
    write_report(lines, args.out)
    return 0


def _paddle(count: int) -> dict[str, list[physics.Outcome]]:
    rng = np.random.default_rng(11)
    robot = problems.seed_paddle_strike().robot
    found: dict[str, list[physics.Outcome]] = defaultdict(list)
    planner = planners.OptimalControl("time")
    made = 0
    while made < count:
        ball = (rng.uniform(0.5, 1.0), rng.uniform(-0.5, 0.5), rng.uniform(0.1, 0.6))
        try:
            strike = problems.PaddleStrike(robot, ball=ball, speed=PADDLE_SPEED)
            traj = planner.plan(
                dataclasses.replace(strike, limits=robot.limits.scaled(PLAN_MARGIN))
            )
        except OptrajError:
            continue
        made += 1
        found["plan alone"].append(
            physics.outcome(physics.replay(physics.scene_for(strike), traj), strike)
        )
        for label, controller in _controllers(robot):
            plant = physics.MujocoPlant(physics.scene_for(strike))
            result = controllers.simulate(robot, traj, controller, plant=plant, settle=0.05)
            found[label].append(physics.outcome(result, strike))
    return found


if __name__ == "__main__":
    sys.exit(main())
