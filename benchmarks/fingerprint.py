"""A refactoring guard: the numbers every planner and controller gives on fixed seeded cases.

Plans seeded pool strikes with every strike planner, seeded random moves of Sawyer, youBot
and Panda with every joint-space planner, the scenario problems, and tracks two strikes in
closed loop with every controller (one of them in MuJoCo); records each result's iteration
counts, objectives, motion time, numeric metadata, samples of the trajectory and the
independent checker's findings on it, and writes them as JSON. ``--compare`` then lists
every number that moved by more than a tolerance: a change meant to leave behaviour alone
must leave this file alone (wall times excluded).

Usage::

    python benchmarks/fingerprint.py --out /tmp/before        # writes fingerprint.json
    python benchmarks/fingerprint.py --compare /tmp/before /tmp/after [--tolerance 1e-9]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from benchmarking import pool_shots, progress
from optraj import controllers, physics, planners, problems, robots
from optraj.errors import OptrajError

SEED = 20261202
SHOTS = 5  # pool shots per strike planner
MOVES = 4  # random moves per robot
SAMPLES = 25  # trajectory samples recorded per plan
#: Metadata keys that hold wall-clock times (machine noise, not behaviour).
WALL_KEYS = ("time", "seconds", "wall", "clock")
MOTION_KEYS = ("motion_time", "duration", "t_strike", "strike_time")


def _is_wall(key: str) -> bool:
    if any(key.startswith(motion) or key == motion for motion in MOTION_KEYS):
        return False
    return any(part in key for part in WALL_KEYS)


def _numbers(value: Any) -> Any:
    """Value as JSON: floats, ints, bools, strings and lists of them; None when not numeric."""
    if isinstance(value, bool | int | str):
        return value
    if isinstance(value, float | np.floating):
        number = float(value)
        return number if math.isfinite(number) else repr(number)
    if isinstance(value, np.integer | np.bool_):
        return value.item()
    if isinstance(value, np.ndarray) and value.dtype.kind in "fiub" and value.size <= 64:
        return [_numbers(item) for item in value.ravel()]
    if isinstance(value, list | tuple) and len(value) <= 64:
        items = [_numbers(item) for item in value]
        return items if all(item is not None for item in items) else None
    return None


def _trajectory(traj: planners.Trajectory) -> dict[str, Any]:
    record: dict[str, Any] = {"duration": traj.duration}
    for key, value in sorted(traj.metadata.items()):
        if _is_wall(key):
            continue
        number = _numbers(value)
        if number is not None:
            record[f"metadata.{key}"] = number
    times = np.linspace(0.0, traj.duration, SAMPLES)
    sample = traj.sample(times)
    record["q"] = _numbers(sample.q)
    record["qd"] = _numbers(sample.qd)
    record["phases"] = [[p.name, p.t_start, p.t_end] for p in traj.phases]
    return record


def _checked(traj: planners.Trajectory, problem: Any) -> dict[str, Any]:
    """The independent checker's findings on ``traj``: worst value, margin, time, joint."""
    report = planners.check(traj, problem)
    return {
        finding.name: [
            finding.value,
            finding.margin,
            "-" if finding.time is None else finding.time,
            finding.joint or "-",
            finding.ok,
        ]
        for finding in report.findings
    }


def _attempt(plan: Callable[[], planners.Trajectory], problem: Any = None) -> dict[str, Any]:
    try:
        traj = plan()
    except OptrajError as exc:
        return {"error": type(exc).__name__, "message": str(exc)}
    record = _trajectory(traj)
    if problem is not None:
        record["check"] = _checked(traj, problem)
    return record


def _strike_planners() -> list[tuple[str, Any]]:
    return [
        ("pull-back", planners.PullBackStrike()),
        ("cubic", planners.ClassicStrike("cubic", contact="choose")),
        ("quintic", planners.ClassicStrike("quintic", contact="choose")),
        ("lspb", planners.ClassicStrike("lspb", contact="choose")),
        ("toppra", planners.TimeOptimalStrike("toppra", contact="choose")),
        ("ruckig", planners.TimeOptimalStrike("ruckig", contact="choose")),
        ("ocp time", planners.OptimalControl("time")),
        ("ocp jerk", planners.OptimalControl("jerk")),
        ("ocp torque", planners.OptimalControl("time", torque=True)),
        ("ocp rnea", planners.OptimalControl("time", torque=True, torque_rows="rnea")),
    ]


def _joint_planners() -> list[tuple[str, Any]]:
    return [
        ("cubic", planners.Cubic()),
        ("quintic", planners.Quintic()),
        ("lspb", planners.LSPB()),
        ("toppra", planners.Toppra()),
        ("ruckig", planners.Ruckig()),
        ("ocp time", planners.OptimalControl("time")),
    ]


def _moves() -> Iterator[tuple[str, problems.PointToPoint]]:
    rng = np.random.default_rng(SEED)
    for name in ("sawyer", "youbot", "panda"):
        try:
            robot = robots.load(name)
        except OptrajError:
            continue
        low, high = robot.limits.lower, robot.limits.upper
        middle, half = (low + high) / 2, (high - low) / 2
        for index in range(MOVES):
            q0 = middle + 0.5 * half * rng.uniform(-1, 1, robot.dof)
            q1 = middle + 0.5 * half * rng.uniform(-1, 1, robot.dof)
            yield f"{name} move {index}", problems.PointToPoint(robot, q_start=q0, q_goal=q1)


def cases() -> Iterator[tuple[str, Callable[[], dict[str, Any]]]]:
    """(name, run) of every case, in a fixed order."""
    shots, _ = pool_shots(SHOTS, seed=SEED)
    for index, shot in enumerate(shots):
        for label, planner in _strike_planners():
            yield f"shot {index} {label}", lambda p=planner, s=shot: _attempt(lambda: p.plan(s), s)
    for name, move in _moves():
        for label, planner in _joint_planners():
            yield f"{name} {label}", lambda p=planner, m=move: _attempt(lambda: p.plan(m), m)
        yield f"{name} lower bound", lambda m=move: {"value": planners.lower_bound(m)}
    paddle = problems.ece486_paddle_strike()
    for label, planner in [("cubic", planners.Cubic()), ("ocp", planners.OptimalControl())]:
        yield f"paddle {label}", lambda p=planner: _attempt(lambda: p.plan(paddle), paddle)
    blocks = problems.youbot_two_blocks()
    yield (
        "youbot blocks",
        lambda: _attempt(lambda: planners.PickAndPlacePlanner().plan(blocks), blocks),
    )
    for index, shot in enumerate(shots[:2]):
        yield f"tracking {index}", lambda s=shot: _tracking(s)
    yield "ocp warm re-plan", lambda: _warm(shots[0], shots[0])


def _warm(first: problems.PoolStrike, second: problems.PoolStrike) -> dict[str, Any]:
    planner = planners.OptimalControl("time")
    try:
        previous = planner.plan(first)
    except OptrajError as exc:
        return {"error": type(exc).__name__}
    return _attempt(lambda: planner.plan(second, warm_start=previous))


def _metrics(result: controllers.simulation.Result) -> dict[str, Any]:
    metrics = result.metrics
    record: dict[str, Any] = {
        "position_rms": metrics.position_rms,
        "position_max": metrics.position_max,
        "fallbacks": metrics.fallbacks,
    }
    if metrics.strike is not None:
        record["line_max"] = metrics.strike.line_max
        record["speed_error_max"] = metrics.strike.speed_error_max
    return record


def _tracking(shot: problems.PoolStrike) -> dict[str, Any]:
    try:
        traj = planners.OptimalControl("time").plan(shot)
    except OptrajError as exc:
        return {"error": type(exc).__name__}
    robot = shot.robot
    record: dict[str, Any] = {}
    for label, controller in [
        ("pinv", controllers.PseudoInversePID(robot)),
        ("qp", controllers.DiffIKQP(robot)),
        ("pd", controllers.JointPD(robot)),
    ]:
        result = controllers.simulate(robot, traj, controller, 1e-3, plant="dynamic")
        record[label] = _metrics(result)
    scene = physics.pool_scene(robot, ball=shot.ball)
    result = controllers.simulate(
        robot, traj, controllers.DiffIKQP(robot), 1e-3, plant=physics.MujocoPlant(scene)
    )
    ball = physics.outcome(result, shot)
    record["mujoco"] = {
        "heading_error": ball.heading_error,
        "speed_error": ball.speed_error,
        **_metrics(result),
    }
    return record


def write(out: Path) -> Path:
    """Run every case and write ``out/fingerprint.json``; returns the file."""
    listed = list(cases())
    record: dict[str, Any] = {}
    for index, (name, run) in enumerate(listed):
        progress(index, len(listed), "fingerprint")
        record[name] = run()
    progress(len(listed), len(listed), "fingerprint")
    out.mkdir(parents=True, exist_ok=True)
    path = out / "fingerprint.json"
    path.write_text(json.dumps(_numbers_tree(record), indent=1, sort_keys=True))
    return path


def _numbers_tree(value: Any) -> Any:
    if isinstance(value, dict):
        return {key: _numbers_tree(item) for key, item in value.items()}
    number = _numbers(value)
    return number if number is not None else repr(value)


def differences(before: Any, after: Any, tolerance: float, where: str = "") -> Iterator[str]:
    """Every place where ``after`` differs from ``before`` by more than ``tolerance``.

    Numbers compare by ``|a - b| <= tolerance * max(1, |a|)``; everything else exactly.
    """
    if isinstance(before, dict) and isinstance(after, dict):
        for key in sorted(set(before) | set(after)):
            if key not in before or key not in after:
                yield f"{where}/{key}: only {'after' if key in after else 'before'}"
            else:
                yield from differences(before[key], after[key], tolerance, f"{where}/{key}")
    elif isinstance(before, list) and isinstance(after, list) and len(before) == len(after):
        for index, (a, b) in enumerate(zip(before, after, strict=True)):
            yield from differences(a, b, tolerance, f"{where}[{index}]")
    elif isinstance(before, int | float) and isinstance(after, int | float):
        if abs(before - after) > tolerance * max(1.0, abs(before)):
            yield f"{where}: {before!r} -> {after!r}"
    elif before != after:
        yield f"{where}: {before!r} -> {after!r}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="folder to write fingerprint.json into")
    parser.add_argument("--compare", type=Path, nargs=2, metavar=("BEFORE", "AFTER"))
    parser.add_argument("--tolerance", type=float, default=1e-9, help="relative, default 1e-9")
    args = parser.parse_args(argv)
    if args.compare is not None:
        before, after = (json.loads((p / "fingerprint.json").read_text()) for p in args.compare)
        found = list(differences(before, after, args.tolerance))
        print("\n".join(found) if found else f"identical to {args.tolerance:g}")
        return 1 if found else 0
    if args.out is None:
        parser.error("give --out DIR or --compare BEFORE AFTER")
    print(write(args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
