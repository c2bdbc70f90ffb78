"""``optraj demo``: the main job, from the robots to a tracked pool shot.

It prints every robot's joints, limits and tool pose at home, reproduces the ECE486 seed's
paddle table, shows the independent checker's verdict on classic plans, then plans the Sawyer
pool shot at 1 m/s with every strike planner, checks each plan, tracks the minimum-time
optimal-control plan (planned within 80 % of the limits) with the seed's pseudo-inverse PID and
the differential-IK QP, strikes the ball with the plan alone and with each controller in a
MuJoCo world (where the ball went), and writes plots (PNG) and plans (JSON) to the output
directory.

Everything heavy is imported inside the functions, so that ``import optraj`` stays cheap.
"""

from __future__ import annotations

import argparse
import functools
import math
import re
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TextIO

from optraj.errors import InvalidInputError, MissingDependencyError, OptrajError

__all__ = ["run", "short_reason", "strike_section", "write_plots"]

#: The shot every planner plans, and how it is checked.
SHOT_SPEED = 1.0  # [m/s]
QUANTITIES = ("position", "velocity", "acceleration", "jerk")
#: Fraction of the limits the tracked plan is planned within (room for the controllers).
TRACKING_SCALE = 0.8


class Progress:
    """One status line on stderr, rewritten in place; silent unless stderr is a terminal."""

    def __init__(self, stream: TextIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = bool(getattr(self.stream, "isatty", lambda: False)())
        self.started = time.perf_counter()

    def __call__(self, message: str) -> None:
        """Show what is being done now."""
        if self.enabled:
            elapsed = time.perf_counter() - self.started
            self.stream.write(f"\r\033[K[{elapsed:5.1f} s] {message} ...")
            self.stream.flush()

    def done(self) -> None:
        """Clear the status line."""
        if self.enabled:
            self.stream.write("\r\033[K")
            self.stream.flush()


def run(args: argparse.Namespace, out: TextIO) -> int:
    """Run the whole demo; returns the exit status."""
    from optraj import robots

    progress = Progress()
    try:
        out.write("optraj robots: joints, limits (units per row) and the tool pose at home\n")
        missing = []
        for name in robots.known_robots():
            progress(f"loading {name}")
            try:
                _robot_report(name, out)
            except MissingDependencyError as exc:
                if not args.skip_missing:
                    raise
                missing.append(f"{name} ({exc})")
        for line in missing:
            out.write(f"\nskipped {line}\n")
        _seed_table(out)
        progress("checking classic plans")
        _verdicts(out)
        strike_section(Path(args.out), out, progress)
    finally:
        progress.done()
    return 0


# ------------------------------------------------------------------ robots and the seed


def _robot_report(name: str, out: TextIO) -> None:
    import numpy as np
    import pinocchio as pin

    from optraj import robots

    robot = robots.load(name)
    T = robot.tool_pose(robot.home)
    rpy = pin.rpy.matrixToRpy(T[:3, :3])
    out.write(f"\n{robot.name}: {robot.description}\n")
    width = max(len(joint) for joint in ("joint", *robot.joint_names)) + 2
    header = (
        f"  {'joint':<{width}}{'unit':>5}{'lower':>10}{'upper':>10}{'home':>10}"
        f"{'vel':>9}{'acc':>9}{'jerk':>9}{'effort':>9}\n"
    )
    out.write(header)
    for row, q in zip(robot.limits.table(), robot.home, strict=True):
        out.write(
            f"  {row['joint']:<{width}}{row['unit']:>5}{row['lower']:>10.4f}{row['upper']:>10.4f}"
            f"{q:>10.4f}{row['velocity']:>9.3f}{row['acceleration']:>9.2f}{row['jerk']:>9.1f}"
            f"{row['effort']:>9.2f}\n"
        )
    # Adding 0.0 turns -0.0 into 0.0 for printing.
    position = np.array2string(T[:3, 3] + 0.0, precision=4, floatmode="fixed", suppress_small=True)
    angles = np.array2string(
        np.round(np.degrees(rpy), 2) + 0.0, precision=2, floatmode="fixed", suppress_small=True
    )
    out.write(
        f"  tool frame {robot.tool_frame!r} at home: position {position} m, "
        f"roll-pitch-yaw {angles} deg\n"
    )


def _seed_table(out: TextIO) -> None:
    import numpy as np

    from optraj import planners, problems

    problem = problems.seed_paddle_strike()
    traj = planners.Cubic().plan(problem)
    times = np.arange(0.0, problem.contact_time + 1e-9, 1.0 / 5.0)
    out.write(
        "\npaddle4, seed ECE486: ball (1.1, 0.8, 0.7) m from home, cubic, T = 2 s, 5 Hz\n"
        f"  {'t [s]':>6}{'J1 [m]':>9}{'J2 [rad]':>10}{'J3 [m]':>9}{'J4 [rad]':>10}\n"
    )
    for t, q in zip(times, traj.sample(times).q, strict=True):
        out.write(f"  {t:>6.1f}{q[0]:>9.4f}{q[1]:>10.4f}{q[2]:>9.4f}{q[3]:>10.4f}\n")


def _verdicts(out: TextIO) -> None:
    from optraj import planners, problems
    from optraj.cli import describe_failures

    cases: list[tuple[str, Any, Any, tuple[str, ...] | None]] = [
        ("youBot pick and place", planners.PickAndPlacePlanner(planners.Quintic()),
         problems.youbot_two_blocks(), ("position", "velocity", "acceleration", "jerk")),
        ("youBot pick and place", planners.PickAndPlacePlanner(planners.LSPB()),
         problems.youbot_two_blocks(), ("position", "velocity", "acceleration")),
        ("Sawyer pool shot 1 m/s", planners.SeedStrike(), problems.sawyer_pool_shot(), None),
    ]  # fmt: skip
    out.write(
        "\nthe independent checker on classic plans (failures: value as % of the limit)\n"
        f"  {'task':<24}{'planner':<30}{'time [s]':>9}  {'verdict':<8}checked / failing findings\n"
    )
    for task, planner, problem, quantities in cases:
        traj = planner.plan(problem)
        report = planners.check(traj, problem, quantities=quantities)
        if report.violations:
            note = describe_failures(report)
        else:
            note = "+".join(q[:3] for q in (quantities or planners.checker.QUANTITIES)) + ", task"
        verdict = "ok" if report.ok else "FAIL"
        out.write(f"  {task:<24}{planner.name:<30}{traj.duration:>9.3f}  {verdict:<8}{note}\n")


# ------------------------------------------------------------------ the pool shot


def short_reason(exc: BaseException, width: int = 100) -> str:
    """``ErrorClass: first clause of the message``, without asides, at most ``width`` long."""
    message = " ".join(str(exc).split()).split("; ")[0]
    message = re.sub(r"\s*\([^()]*\)", "", message)
    text = f"{type(exc).__name__}: {message}"
    return text if len(text) <= width else text[: width - 3].rstrip() + "..."


def _ratio(value: float) -> str:
    return "inf" if math.isinf(value) else f"{value:.2f}"


def strike_section(out_dir: Path, out: TextIO, progress: Any = None) -> None:
    """Plan, check and track the pool shot; write plots and plans to ``out_dir``."""
    from optraj import planners, problems
    from optraj.cli import PLANNERS, describe_failures, make_planner, tag_trajectory

    progress = progress if progress is not None else (lambda message: None)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InvalidInputError(
            f"cannot create the output directory {str(out_dir)!r}: {exc.strerror}", name="out"
        ) from exc
    problem = problems.sawyer_pool_shot(speed=SHOT_SPEED)
    robot = problem.robot
    options = {"speed": SHOT_SPEED}
    out.write(
        f"\nSawyer pool shot {SHOT_SPEED:g} m/s: every planner (checked: position, velocity, "
        "acceleration, jerk and the task; vel/acc/jerk: peak / limit, worst joint)\n"
        f"  {'planner':<28}{'time [s]':>9}  {'verdict':<8}{'vel':>6}{'acc':>6}{'jerk':>6}"
        f"{'strike pos [mm]':>17}  failing findings / error\n"
    )
    plans: dict[str, Any] = {}
    files: dict[str, Any] = {}
    for key in PLANNERS["pool-shot"]:
        planner = make_planner("pool-shot", key)
        label = planner.name
        progress(f"planning the pool shot: {label}")
        try:
            traj = planner.plan(problem)
        except OptrajError as exc:
            out.write(f"  {label:<28}{'-':>9}  {'error':<8}{'':>18}{'':>17}  {short_reason(exc)}\n")
            continue
        report = planners.check(traj, problem, quantities=QUANTITIES)
        position = report["strike position"].value * 1e3
        out.write(
            f"  {label:<28}{traj.duration:>9.3f}  {'ok' if report.ok else 'FAIL':<8}"
            f"{_ratio(report['velocity'].ratio):>6}{_ratio(report['acceleration'].ratio):>6}"
            f"{_ratio(report['jerk'].ratio):>6}{position:>17.3f}  "
            f"{describe_failures(report) or '-'}\n"
        )
        tag_trajectory(traj, "sawyer", "pool-shot", options)
        plans[label] = traj
        files[f"plan-{key}.json"] = traj

    progress(f"planning within {TRACKING_SCALE:.0%} of the limits")
    runs = _tracking(problem, files, progress, out)
    progress("writing plots and plans")
    written = write_plots(out_dir, robot, plans, runs, out)
    for name, traj in files.items():
        path = out_dir / name
        traj.to_json(path)
        written.append(path)
    if written:
        out.write(f"\nwrote to {out_dir}/: {', '.join(path.name for path in written)}\n")


def _tracking(problem: Any, files: dict[str, Any], progress: Any, out: TextIO) -> list[Any]:
    """Track the min-time plan made within a fraction of the limits; print the table."""
    import dataclasses

    from optraj import controllers, planners
    from optraj.cli import tag_trajectory

    robot = problem.robot
    roomy = dataclasses.replace(problem, limits=robot.limits.scaled(TRACKING_SCALE))
    title = (
        f"\ntracking the minimum-time optimal-control plan, planned within "
        f"{TRACKING_SCALE:.0%} of the limits"
    )
    try:
        traj = planners.OptimalControl(objective="time").plan(roomy)
    except OptrajError as exc:
        out.write(f"{title}: not planned ({short_reason(exc)})\n")
        return []
    tag_trajectory(
        traj, "sawyer", "pool-shot", {"speed": SHOT_SPEED, "limit_scale": TRACKING_SCALE}
    )
    files["plan-optimal-control-tracked.json"] = traj
    out.write(
        f"{title} ({traj.duration:.3f} s), 1 kHz, rigid-body plant\n"
        f"  {'controller':<22}{'tool error':>12}{'strike line':>13}{'strike speed':>14}"
        f"{'commands over':>15}{'worst command':>15}{'median step':>13}\n"
        f"  {'':<22}{'max [mm]':>12}{'error [mm]':>13}{'error [%]':>14}{'a limit':>15}"
        f"{'/ limit':>15}{'time [us]':>13}\n"
    )
    runs = []
    for controller in (controllers.PseudoInversePID(robot), controllers.DiffIKQP(robot)):
        progress(f"tracking with {type(controller).__name__}")
        result = controllers.simulate(robot, traj, controller)
        metrics = result.metrics
        command = metrics.violations["command"]
        strike = metrics.strike
        line = "-" if strike is None else f"{strike.line_max * 1e3:.3f}"
        speed = "-" if strike is None else f"{strike.speed_error_max * 100:.2f}"
        out.write(
            f"  {result.controller:<22}{metrics.position_max * 1e3:>12.3f}{line:>13}{speed:>14}"
            f"{command.count:>15d}{command.worst:>15.3f}{metrics.step_time_median * 1e6:>13.1f}\n"
        )
        runs.append(result)
    progress("striking the ball in MuJoCo")
    _where_the_ball_went(problem, traj, out)
    return runs


def _signed(value: float, digits: int = 3) -> str:
    """``value`` with its sign, never ``-0.000``."""
    return f"{round(value, digits) + 0.0:+.{digits}f}"


def _tracked(robot: Any, traj: Any, controller: Any, scene: Any) -> Any:
    """The controller following the plan in the MuJoCo strike world (0.05 s to settle)."""
    from optraj import controllers, physics

    return controllers.simulate(
        robot, traj, controller, plant=physics.MujocoPlant(scene), settle=0.05
    )


def _where_the_ball_went(problem: Any, traj: Any, out: TextIO) -> None:
    """The plan alone and each controller on the MuJoCo plant: where the ball went."""
    from optraj import controllers, physics

    robot = problem.robot
    scene = physics.scene_for(problem)
    x, y, z = problem.ball
    out.write(
        f"\nwhere the ball went (MuJoCo: cue on a pool ball at ({x:.3f}, {y:.3f}, {z:.3f}) m, "
        f"on target = within {physics.HEADING_TOLERANCE:g} deg and "
        f"{100 * physics.SPEED_TOLERANCE:g} % of the shot)\n"
        f"  {'run':<22}{'heading':>9}{'speed':>8}{'ball speed':>12}{'rest position':>24}"
        "  verdict\n"
        f"  {'':<22}{'[deg]':>9}{'[%]':>8}{'[m/s]':>12}{'x, y [m]':>24}\n"
    )
    runs: list[tuple[str, Callable[[], Any]]] = [
        ("plan alone", lambda: physics.replay(scene, traj))
    ]
    for controller in (controllers.PseudoInversePID(robot), controllers.DiffIKQP(robot)):
        runs.append((controller.name, functools.partial(_tracked, robot, traj, controller, scene)))
    for label, run in runs:
        try:
            ball = physics.outcome(run(), problem)
        except OptrajError as exc:
            out.write(f"  {label:<22}{'-':>9}{'-':>8}{'-':>12}{'-':>24}  {short_reason(exc)}\n")
            continue
        if not ball.hit:
            out.write(f"  {label:<22}{'-':>9}{'-':>8}{'-':>12}{'-':>24}  missed the ball\n")
            continue
        rest = f"{ball.rest_position[0]:.3f}, {ball.rest_position[1]:.3f}"
        out.write(
            f"  {label:<22}{_signed(ball.heading_error):>9}{_signed(100 * ball.speed_error, 2):>8}"
            f"{ball.launch_speed:>12.3f}{rest:>24}  {'on target' if ball.within else 'OFF'}\n"
        )


def write_plots(
    out_dir: Path, robot: Any, plans: dict[str, Any], runs: list[Any], out: TextIO
) -> list[Path]:
    """Write ``profiles.png``, ``tool_speed.png`` and ``tracking.png``; returns the paths.

    Without matplotlib, prints one line saying the plots were skipped and returns [].
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from optraj import controllers
        from optraj.planners import plot as plotting
    except ImportError:
        out.write("\nplots skipped: matplotlib is not installed (pip install 'optraj[examples]')\n")
        return []
    figures = []
    try:
        if plans:
            figures.append(("profiles.png", plotting.plot_profiles(plans, robot.limits)))
            figures.append(("tool_speed.png", plotting.plot_tool_speed(robot, plans)))
        if runs:
            figures.append(("tracking.png", controllers.plot_tracking(runs, robot.limits)))
    except MissingDependencyError:
        out.write("\nplots skipped: matplotlib is not installed (pip install 'optraj[examples]')\n")
        return []
    written: list[Path] = []
    for name, figure in figures:
        path = out_dir / name
        figure.savefig(path, dpi=110)
        plt.close(figure)
        written.append(path)
    return written
