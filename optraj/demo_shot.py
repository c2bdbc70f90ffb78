"""The pool shot of ``optraj demo``: what each planner did and why, tracking, the ball.

:func:`planner_section` plans the Sawyer pool shot with every pool-shot planner, checks each
plan with the independent checker and says in one line per planner (one line for planners
refused for the same reason) what it did and why; :func:`tracking_section` tracks the
minimum-time optimal-control plan with both controllers; :func:`ball_section` strikes the ball
in MuJoCo with that plan alone and with each controller, and says where the ball went.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TextIO

from optraj.errors import OptrajError

__all__ = [
    "QUANTITIES",
    "TRACKING_SCALE",
    "Attempt",
    "ball_section",
    "planner_label",
    "planner_section",
    "short_reason",
    "tracking_section",
]

#: What every plan is checked for (with the strike line).
QUANTITIES = ("position", "velocity", "acceleration", "jerk")
#: Fraction of the limits the tracked plan is planned within (room for the controllers).
TRACKING_SCALE = 0.8
#: What the planners are called in the demo's text, where their own names say too little.
LABELS = {"pull-back": "pull-back + constant-speed strike"}
#: Why a planner that plans the shot breaks a limit, by command-line name.
WHY_IT_FAILS = {
    "pull-back": "it starts the strike line at full speed from rest, so the cue's velocity jumps",
}


@dataclass
class Attempt:
    """One planner on the shot: its plan and the checker's report, or why it refused."""

    key: str
    label: str
    traj: Any = None
    report: Any = None
    error: OptrajError | None = None


def planner_label(key: str, planner: Any) -> str:
    """What a planner is called in the demo: its name, or what it does."""
    return LABELS.get(key, str(planner.name))


def short_reason(exc: BaseException, width: int = 100) -> str:
    """``ErrorClass: first clause of the message``, without asides, at most ``width`` long."""
    message = " ".join(str(exc).split()).split("; ")[0]
    message = re.sub(r"\s*\([^()]*\)", "", message)
    text = f"{type(exc).__name__}: {message}"
    return text if len(text) <= width else text[: width - 3].rstrip() + "..."


def _ratio(value: float) -> str:
    return "unbounded" if math.isinf(value) else f"{value:.0%}"


def plan_every_planner(problem: Any, progress: Callable[[str], None]) -> list[Attempt]:
    """Plan ``problem`` (a pool shot) with every pool-shot planner; check each plan."""
    from optraj import planners
    from optraj.cli import PLANNERS, make_planner

    attempts = []
    for key in PLANNERS["pool-shot"]:
        planner = make_planner("pool-shot", key)
        attempt = Attempt(key, planner_label(key, planner))
        progress(f"planning the pool shot: {attempt.label}")
        try:
            attempt.traj = planner.plan(problem)
        except OptrajError as exc:
            attempt.error = exc
        else:
            attempt.report = planners.check(attempt.traj, problem, quantities=QUANTITIES)
        attempts.append(attempt)
    return attempts


def _planned_line(attempt: Attempt) -> str:
    """One line: a plan the checker passed or failed, and why."""
    from optraj.cli import describe_failures

    report = attempt.report
    head = f"  {attempt.label:<34}{attempt.traj.duration:>6.3f} s  "
    if not report.ok:
        why = WHY_IT_FAILS.get(attempt.key, "the checker finds limits broken")
        return f"{head}FAIL  {why}: {describe_failures(report)}\n"
    peaks = ", ".join(
        f"{name} {_ratio(report[name].ratio)}" for name in ("velocity", "acceleration", "jerk")
    )
    line = report["strike position"].value * 1e3
    return f"{head}ok    within every limit (peaks {peaks}), cue {line:.3f} mm off the line\n"


def planner_section(problem: Any, attempts: list[Attempt], out: TextIO) -> None:
    """Print what each planner did with the shot, and why optimal control succeeds."""
    out.write(
        "\nwhat each planner did (every plan judged by the independent checker: joint limits "
        "and the strike line)\n"
    )
    refused: dict[str, list[Attempt]] = {}
    for attempt in attempts:
        if attempt.error is None:
            out.write(_planned_line(attempt))
        else:
            reason = short_reason(attempt.error, width=400).split(": ", 1)[1]
            refused.setdefault(reason, []).append(attempt)
    for reason, group in refused.items():
        names = ", ".join(attempt.label.removesuffix(" strike") for attempt in group)
        what = f"{names} strike{'s' if len(group) > 1 else ''}"
        out.write(f"  {what}: refused, {reason} at the problem's contact configuration\n")
    best = next((a for a in attempts if a.traj is not None and a.report.ok), None)
    if best is not None and refused:
        ratio = best.traj.metadata.get("contact_speed_ratio")
        share = (
            f" (the line there needs at most {ratio:.0%} of a joint's speed limit)" if ratio else ""
        )
        out.write(
            f"  why {best.label} succeeds: it chooses where the cue meets the ball{share} and "
            "plans approach, strike and stop as one problem, every limit a constraint\n"
        )


def tracking_section(problem: Any, progress: Callable[[str], None], out: TextIO) -> Any:
    """Track the min-time plan made within a fraction of the limits; returns (plan, runs)."""
    import dataclasses

    from optraj import controllers, planners

    robot = problem.robot
    roomy = dataclasses.replace(problem, limits=robot.limits.scaled(TRACKING_SCALE))
    title = (
        f"\ntracking: the minimum-time optimal-control plan made within {TRACKING_SCALE:.0%} of "
        "the limits"
    )
    progress(f"planning within {TRACKING_SCALE:.0%} of the limits")
    try:
        traj = planners.OptimalControl(objective="time").plan(roomy)
    except OptrajError as exc:
        out.write(f"{title}: not planned ({short_reason(exc)})\n")
        return None, []
    out.write(
        f"{title} ({traj.duration:.3f} s), followed at 1 kHz on the rigid-body arm\n"
        f"  {'controller':<22}{'tool error':>14}{'off the line':>14}{'speed error':>13}"
        f"{'worst command':>15}{'step time':>11}\n"
    )
    runs = []
    for controller in (controllers.PseudoInversePID(robot), controllers.DiffIKQP(robot)):
        progress(f"tracking with {controller.name}")
        result = controllers.simulate(robot, traj, controller)
        metrics = result.metrics
        strike = metrics.strike
        line = "-" if strike is None else f"{strike.line_max * 1e3:.3f} mm"
        speed = "-" if strike is None else f"{strike.speed_error_max * 100:.2f} %"
        worst = metrics.violations["command"].worst
        out.write(
            f"  {result.controller:<22}{metrics.position_max * 1e3:>11.3f} mm{line:>14}"
            f"{speed:>13}{worst:>9.0%} limit{metrics.step_time_median * 1e6:>8.1f} us\n"
        )
        runs.append(result)
    return traj, runs


def _signed(value: float, digits: int = 3) -> str:
    """``value`` with its sign, never ``-0.000``."""
    return f"{round(value, digits) + 0.0:+.{digits}f}"


def _tracked(robot: Any, traj: Any, controller: Any, scene: Any) -> Any:
    """The controller following the plan in the MuJoCo strike world (0.05 s to settle)."""
    from optraj import controllers, physics

    return controllers.simulate(
        robot, traj, controller, plant=physics.MujocoPlant(scene), settle=0.05
    )


def ball_section(problem: Any, traj: Any, progress: Callable[[str], None], out: TextIO) -> Any:
    """Strike the ball in MuJoCo with the plan alone and each controller; returns one outcome.

    The outcome returned is the differential-IK QP's (None when none hit the ball).
    """
    from optraj import controllers, physics

    robot = problem.robot
    scene = physics.scene_for(problem)
    out.write(
        f"\nwhere the ball went (MuJoCo; on target: within {physics.HEADING_TOLERANCE:g} deg "
        f"and {100 * physics.SPEED_TOLERANCE:g} % of the shot)\n"
        f"  {'run':<22}{'heading error':>14}{'speed error':>13}{'ball speed':>12}"
        f"{'rests at x, y':>16}  verdict\n"
    )
    runs: list[tuple[str, Callable[[], Any]]] = [
        ("plan alone", lambda: physics.replay(scene, traj))
    ]
    for controller in (controllers.PseudoInversePID(robot), controllers.DiffIKQP(robot)):
        runs.append((controller.name, functools.partial(_tracked, robot, traj, controller, scene)))
    last = None
    for label, run in runs:
        progress(f"striking the ball in MuJoCo: {label}")
        try:
            ball = physics.outcome(run(), problem)
        except OptrajError as exc:
            out.write(f"  {label:<22}{short_reason(exc)}\n")
            continue
        if not ball.hit:
            out.write(f"  {label:<22}missed the ball\n")
            continue
        last = ball
        rest = f"{ball.rest_position[0]:.2f}, {ball.rest_position[1]:.2f} m"
        heading, speed = _signed(ball.heading_error), _signed(100 * ball.speed_error, 2)
        out.write(
            f"  {label:<22}{heading:>10} deg{speed:>11} %"
            f"{ball.launch_speed:>8.3f} m/s{rest:>16}  {'on target' if ball.within else 'OFF'}\n"
        )
    return last
