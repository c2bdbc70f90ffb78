"""What the scene costs: the clearance check against the rest of the checker, and pick-and-place.

1. The checker's ``clearance`` finding against everything else it finds, on one trajectory
   (the youBot two-block task planned with its scene, vertical lines, Quintic): the rest is
   ``planners.check(traj, problem)`` without a scene (every limit and task finding), the
   clearance is ``planners.check(traj, robot, scene=..., quantities=[])`` (that finding
   alone), both at the checker's default 1 kHz; the two are timed in turn, ``--repeats``
   times, in this one process, and the medians are compared, per second of trajectory.
2. The pick-and-place motion time with and without the scene: today's plan (joint moves, the
   interim pose at the start pose, no scene) against the scene-aware one (the interim pose
   from the scene, vertical lines down to and up from each grasp and release), for Quintic and
   LSPB moves; with the smallest distance of each to the blocks it does not hold (the
   2 cm requirement of issue 37, :func:`problems.scenarios.block_clearance_scene`).

Prints a Markdown table and writes it to ``--out`` (a file; never the committed results).

Usage: ``python benchmarks/clearance.py --out /tmp/clearance.md [--repeats 5 | --quick]``
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from benchmarking import write_report
from optraj import planners, problems
from optraj.planners.base import JointProfile
from optraj.problems.scenarios import block_clearance_scene
from optraj.problems.scene_distances import SceneCollision

REPEATS = 5
#: Timed runs of each check with ``--quick`` (as ``run_all.py --quick`` passes it).
QUICK_REPEATS = 2


def _seconds(run: Callable[[], object]) -> float:
    started = time.perf_counter()
    run()
    return time.perf_counter() - started


def cost_rows(repeats: int) -> list[str]:
    """Table rows: the clearance finding's cost and the rest's, per second of trajectory."""
    task = problems.youbot_two_blocks(with_scene=True)
    traj = planners.PickAndPlacePlanner(planners.Quintic(), vertical=True).plan(task)
    bare = dataclasses.replace(task, scene=None)

    def rest() -> object:
        return planners.check(traj, bare)

    def clearance() -> object:
        return planners.check(traj, task.robot, scene=task.scene, quantities=[])

    rest(), clearance()  # warm-up: imports and caches
    times: dict[str, list[float]] = {"rest": [], "clearance": []}
    for _ in range(repeats):  # interleaved, so that both see the same machine load
        times["rest"].append(_seconds(rest))
        times["clearance"].append(_seconds(clearance))
    rest_s = statistics.median(times["rest"])
    clear_s = statistics.median(times["clearance"])
    pairs = SceneCollision(task.robot, task.scene).pair_count if task.scene else 0
    duration = traj.duration
    return [
        f"## Clearance check cost (youBot two blocks, {duration:.2f} s trajectory, 1 kHz, "
        f"median of {repeats})",
        "",
        "| check | time [s] | per second of trajectory [s/s] | ratio to the rest |",
        "|---|---:|---:|---:|",
        f"| rest of the checker (limits + task) | {rest_s:.3f} | {rest_s / duration:.4f} | 1 |",
        f"| clearance | {clear_s:.3f} | {clear_s / duration:.4f} | {clear_s / rest_s:.2f} |",
        "",
        f"({pairs} collision pairs (robot-robot, robot-object, carried block-object), each "
        f"measured by coal at every 1 ms sample and breakpoint)",
    ]


def _plan_row(
    label: str, profile: JointProfile, task: problems.PickAndPlace, vertical: bool
) -> str:
    started = time.perf_counter()
    traj = planners.PickAndPlacePlanner(profile, vertical=vertical).plan(task)
    plan_s = time.perf_counter() - started
    judged = task if task.scene is not None else _with_scene(task)
    report = planners.check(traj, judged)
    scene = report["clearance"]
    blocks = planners.check(traj, judged, scene=block_clearance_scene(judged), quantities=[])
    near = blocks["clearance"]
    failing = [f.name for f in report.findings if not f.ok]
    return (
        f"| {label} | {profile.name} | {traj.duration:.3f} | {plan_s:.2f} | "
        f"{scene.value * 1e3:.2f} | {near.value * 1e3:.2f} | {'ok' if near.ok else 'FAIL'} | "
        f"{', '.join(failing) or '-'} |"
    )


def _with_scene(task: problems.PickAndPlace) -> problems.PickAndPlace:
    """Today's problem judged with its scene (its interim pose kept)."""
    return dataclasses.replace(task, scene=problems.pick_and_place_scene(task))


def duration_rows() -> list[str]:
    """Table rows: motion time with and without the scene, Quintic and LSPB."""
    today = problems.youbot_two_blocks()
    aware = problems.youbot_two_blocks(with_scene=True)
    rows = [
        "## Pick-and-place with and without the scene (youBot two blocks)",
        "",
        "| plan | moves | motion time [s] | plan time [s] | scene clearance [mm] | "
        "nearest block not held [mm] | >= 20 mm | failing findings |",
        "|---|---|---:|---:|---:|---:|---|---|",
    ]
    for profile in (planners.Quintic(), planners.LSPB()):
        rows.append(_plan_row("joint moves, interim = start (today)", profile, today, False))
        rows.append(_plan_row("scene: interim from it, vertical lines", profile, aware, True))
    rows += [
        "",
        "Scene clearance: the smallest distance of the problem's scene "
        "(pick_and_place_scene, margin 0); nearest block not held: the smallest distance of "
        "block_clearance_scene (gripper allowed at the block it handles and the one under it).",
    ]
    return rows


def main(argv: list[str] | None = None) -> int:
    """Run both parts, print the table and write it to ``--out``."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="Markdown file to write")
    parser.add_argument("--repeats", type=int, default=REPEATS, help="timed runs of each check")
    parser.add_argument("--quick", action="store_true", help=f"{QUICK_REPEATS} timed runs")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be >= 1, got {args.repeats}")
    repeats = QUICK_REPEATS if args.quick else args.repeats
    write_report([*cost_rows(repeats), "", *duration_rows()], args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
