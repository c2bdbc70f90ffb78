"""Tracking pool strikes on Sawyer: pseudo-inverse + PID, the differential-IK QP and joint PD.

For the seeded shots of the strike benchmark, each shot is planned twice with
``OptimalControl("time")``: within 80 % of the velocity, acceleration and jerk limits (the
"nominal" plan, leaving room for feedback) and on the full limits. Every controller then
follows the plan in closed loop (``controllers.simulate``, dynamic plant, 1 kHz) under
these conditions:

* nominal: the 80 % plan, nothing else;
* noisy: measurement noise 1e-4 rad and 1e-3 rad/s (seeded per shot);
* latent: commands arrive 5 steps (5 ms) late;
* disturbed: a 20 N push down on the cue tip for 10 ms, 0.1 s before the strike;
* at the limits: the full-limit plan, where several joints run at their speed limit.

The table gives medians over the shots of the tool and strike errors, how many runs
commanded a joint beyond a limit, the worst command over its limit, and the controller
time per step. A second table times one step of each controller on the same states, next
to pink's ``solve_ik`` on the same task when pin-pink is installed.

Writes ``benchmarks/results/tracking.md`` (or ``--out``) and prints it.

Usage: ``python benchmarks/tracking.py [--shots 20] [--quick] [--out PATH]``
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import statistics
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from benchmarking import SEED, SPEED, pool_shots, progress, shot_arguments, write_report
from optraj import controllers, problems
from optraj.controllers.simulation import Impulse, Noise, Result, simulate
from optraj.errors import CompilerError, OptrajError
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.planners.trajectory import Trajectory
from optraj.robots import Robot

RESULTS = Path(__file__).resolve().parent / "results"

PLAN_MARGIN = 0.8  # nominal plans use this fraction of the velocity/acceleration/jerk limits
DT = 1e-3  # control period [s]
LATENCY = 5  # steps
PUSH = 20.0  # force on the cue tip [N], for PUSH_DURATION
PUSH_DURATION = 0.01  # [s]
PUSH_LEAD = 0.1  # the push starts this long before the strike [s]
QP_LABEL = "differential-IK QP"  # the row other controllers are compared with
CONDITIONS = ("nominal", "noisy", "latent", "disturbed", "at the limits")


def controllers_to_compare(robot: Robot) -> list[tuple[str, controllers.Controller]]:
    """The (row label, controller) pairs, in row order."""
    return [
        ("pseudo-inverse PID", controllers.PseudoInversePID(robot)),
        ("differential-IK QP", controllers.DiffIKQP(robot)),
        ("joint PD", controllers.JointPD(robot)),
    ]


def plans(shot: problems.PoolStrike) -> dict[str, Trajectory] | None:
    """The nominal and the full-limit plan of a shot, or None when either fails."""
    planner = OptimalControl("time")
    try:
        nominal = planner.plan(
            dataclasses.replace(shot, limits=shot.robot.limits.scaled(PLAN_MARGIN))
        )
        full = planner.plan(shot)
    except OptrajError:
        return None
    return {"nominal": nominal, "full": full}


def run_condition(
    robot: Robot,
    planned: dict[str, Trajectory],
    controller: controllers.Controller,
    condition: str,
    seed: int,
) -> Result:
    """One closed-loop run of a controller under a condition."""
    traj = planned["full" if condition == "at the limits" else "nominal"]
    options: dict[str, Any] = {}
    if condition == "noisy":
        options["noise"] = Noise(position=1e-4, velocity=1e-3, seed=seed)
    elif condition == "latent":
        options["latency"] = LATENCY
    elif condition == "disturbed":
        start = traj.phase("strike").t_start - PUSH_LEAD
        options["disturbance"] = Impulse(start, [0.0, 0.0, -PUSH], PUSH_DURATION)
    return simulate(robot, traj, controller, DT, plant="dynamic", **options)


class Tally:
    """Metrics of one (condition, controller) row over the shots (a plain class: see strike.py)."""

    def __init__(self) -> None:
        self.position_max: list[float] = []  # [m]
        self.line_max: list[float] = []  # [m]
        self.speed_error: list[float] = []  # [-]
        self.direction: list[float] = []  # [rad]
        self.over_limit = 0  # runs commanding a joint beyond a limit
        self.worst_command: list[float] = []  # |command| / limit, worst joint [-]
        self.fallbacks = 0
        self.step_time: list[float] = []  # [s]

    def record(self, result: Result) -> None:
        """One run."""
        metrics = result.metrics
        strike = metrics.strike
        self.position_max.append(metrics.position_max)
        if strike is not None:
            self.line_max.append(strike.line_max)
            self.speed_error.append(strike.speed_error_max)
            self.direction.append(strike.direction_max)
        command = metrics.violations["command"]
        self.over_limit += command.count > 0
        self.worst_command.append(command.worst)
        self.fallbacks += metrics.fallbacks
        self.step_time.append(metrics.step_time_median)


def _median(values: list[float], scale: float = 1.0, digits: int = 3) -> str:
    return f"{scale * statistics.median(values):.{digits}f}" if values else "-"


def tracking_table(
    tallies: dict[tuple[str, str], Tally], runs: int, labels: list[str]
) -> list[str]:
    """The Markdown table, one row per (condition, controller)."""
    rows = [
        "| condition | controller | tool error max [mm] | strike line error [mm] "
        "| strike speed error [%] | strike direction error [deg] | runs over a limit "
        "| worst command / limit | fallbacks | step time [us] |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for condition in CONDITIONS:
        for label in labels:
            tally = tallies[(condition, label)]
            cells = [
                _median(tally.position_max, 1e3),
                _median(tally.line_max, 1e3),
                _median(tally.speed_error, 1e2, 2),
                _median(tally.direction, math.degrees(1.0), 2),
                f"{tally.over_limit}/{runs}",
                f"{max(tally.worst_command):.3f}" if tally.worst_command else "-",
                str(tally.fallbacks),
                _median(tally.step_time, 1e6, 1),
            ]
            rows.append(f"| {condition} | {label} | {' | '.join(cells)} |")
    return rows


def pink_stepper(
    robot: Robot, solver: str = "osqp"
) -> Callable[[controllers.State, controllers.Reference], Any] | None:
    """One call of pink's ``solve_ik`` on the same task, or None without pin-pink.

    The task: the tool pose (position and orientation cost 1), a posture task towards the
    planned joints (cost 1e-3), pink's default configuration and velocity limits; ``solver``
    is the QP solver pink calls (a qpsolvers name).
    """
    if importlib.util.find_spec("pink") is None:
        return None
    import pink  # optional dependency
    from pink.tasks import FrameTask, PostureTask

    configuration = pink.Configuration(robot.model, robot.model.createData(), robot.home)
    frame = FrameTask(robot.tool_frame, position_cost=1.0, orientation_cost=1.0)
    posture = PostureTask(cost=1e-3)

    def step(state: controllers.State, reference: controllers.Reference) -> Any:
        configuration.update(state.q)
        T = reference.T_world_tool
        frame.set_target(pin.SE3(T[:3, :3], T[:3, 3]))
        posture.set_target(reference.q)
        return pink.solve_ik(configuration, [frame, posture], DT, solver=solver, damping=1e-6)

    return step


def recorded_steps(
    robot: Robot, traj: Trajectory
) -> list[tuple[controllers.State, controllers.Reference]]:
    """The (state, reference) of every step of one closed-loop run of the QP."""
    recorded = simulate(robot, traj, controllers.DiffIKQP(robot), DT, plant="dynamic")
    return [
        (
            controllers.State(float(recorded.t[k]), recorded.q[k], recorded.qd[k]),
            recorded.references[k],
        )
        for k in range(len(recorded.t) - 1)
    ]


def _timing_cases(
    robot: Robot, nominal: list[Any], full: list[Any], with_pink: bool
) -> list[tuple[str, controllers.Controller | None, list[Any]]]:
    """(row label, controller or None for pink, recorded steps) of the timing table."""
    compared = controllers_to_compare(robot)
    qp_controller = next(c for _, c in compared if isinstance(c, controllers.DiffIKQP))
    cases: list[tuple[str, controllers.Controller | None, list[Any]]] = [
        (label, controller, nominal) for label, controller in compared
    ]
    cases.append((f"{QP_LABEL}, run on the full limits", qp_controller, full))
    try:
        compiled: controllers.DiffIKQP | None = controllers.DiffIKQP(robot, evaluation="compiled")
    except CompilerError:
        compiled = None
    if compiled is not None:
        cases.append((f"{QP_LABEL}, compiled to C", compiled, nominal))
    pieces = controllers.DiffIKQP(robot, evaluation="pieces")
    cases.append((f"{QP_LABEL}, from the pieces", pieces, nominal))
    if with_pink:
        cases.append(("pink solve_ik (OSQP)", None, nominal))
    return cases


def _time_steps(
    cases: list[tuple[str, controllers.Controller | None, list[Any]]],
    repeats: int,
    pink_step: Callable[..., Any] | None,
) -> tuple[dict[str, list[float]], dict[str, list[str]]]:
    """Wall time of every step of every case [s], and how each QP step was solved."""
    timed: dict[str, list[float]] = {}
    paths: dict[str, list[str]] = {}
    with warnings.catch_warnings():
        # Through pink, qpsolvers warns on every call that it converts dense matrices to
        # sparse ones, and osqp that a default will change.
        warnings.filterwarnings("ignore", module="qpsolvers")
        warnings.filterwarnings("ignore", module="osqp")
        for _ in range(repeats):  # interleaved, so that machine noise hits every row alike
            for label, controller, steps in cases:
                times = timed.setdefault(label, [])
                if controller is not None:
                    controller.reset(steps[0][0])
                for state, reference in steps:
                    started = time.perf_counter()
                    if controller is None:
                        pink_step(state, reference)  # type: ignore[misc]
                    else:
                        controller.step(state, reference, DT)
                    times.append(time.perf_counter() - started)
                    if isinstance(controller, controllers.DiffIKQP):
                        solver = controller.diagnostics.get("solver", "fallback")
                        paths.setdefault(label, []).append(solver)
    return timed, paths


def _timing_row(label: str, times: list[float], qp: float, paths: dict[str, list[str]]) -> str:
    """One row of the timing table: median, p95, ratio to the QP, steps solved by OSQP."""
    median = statistics.median(times)
    p95 = float(np.percentile(times, 95))
    row = f"| {label} | {1e6 * median:.1f} | {1e6 * p95:.1f} | {median / qp:.2f} |"
    if label not in paths:
        return row + " |"
    through = [t for t, p in zip(times, paths[label], strict=True) if p == "osqp"]
    share = f"{len(through)}/{len(times)}"
    if through:
        share += f", {1e6 * statistics.median(through):.1f} us median"
    return row + f" {share} |"


def timing_table(robot: Robot, planned: dict[str, Trajectory], repeats: int) -> list[str]:
    """Controller time per step on the states of recorded runs, every controller in turn.

    Every controller replays the nominal run; the QP also replays the run on the full limits,
    where its bounds bind and its active set changes more often.
    """
    nominal = recorded_steps(robot, planned["nominal"])
    full = recorded_steps(robot, planned["full"])
    pink_step = pink_stepper(robot)
    cases = _timing_cases(robot, nominal, full, pink_step is not None)
    timed, paths = _time_steps(cases, repeats, pink_step)
    qp = statistics.median(timed[QP_LABEL])
    lines = [
        "",
        "## Controller time per step",
        "",
        f"Sawyer (7 joints), the {len(nominal)} states of one nominal run replayed {repeats} "
        "times, each step including the tool pose and Jacobian; for the QP also the "
        f"{len(full)} states of the same shot's run on the full limits. Goal for the QP: "
        "20 us median.",
        "",
        "| controller | median [us] | p95 [us] | vs QP | QP steps solved by OSQP |",
        "|---|---|---|---|---|",
    ]
    lines += [_timing_row(label, times, qp, paths) for label, times in timed.items()]
    lines += [
        "",
        "A QP step first solves exactly on the last step's active set (one small linear",
        "solve, kept only when it meets the optimality conditions), then changes that set",
        "(at most `active_set_changes` times, one linear solve each); OSQP solves the steps",
        'where that does not settle. By default (`evaluation="fused"`) one CasADi function',
        "computes the tool pose, Jacobian, PID law, the QP's numbers and the solve on the last",
        'active set, evaluated by CasADi\'s virtual machine; `"compiled"` compiles that',
        'function to C with gcc; `"pieces"` assembles the QP from `controllers.qp_terms`',
        "with NumPy at every step. All three give the same commands to round-off.",
    ]
    if not any(label.endswith("compiled to C") for label, _, _ in cases):
        lines += ["", "No C compiler (gcc) was found: the compiled row is missing."]
    if pink_step is None:
        lines += ["", "pin-pink is not installed: `pip install pin-pink` adds its row."]
    return lines


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the Markdown tables."""
    args = shot_arguments(argv, __doc__, 20, 2, RESULTS / "tracking.md")
    out = args.out
    started = time.perf_counter()
    shots, _ = pool_shots(args.shots)
    robot = shots[0].robot
    labels = [label for label, _ in controllers_to_compare(robot)]
    tallies = {(c, label): Tally() for c in CONDITIONS for label in labels}
    planned_shots: list[dict[str, Trajectory]] = []
    unplanned = 0
    for index, shot in enumerate(shots):
        progress(index, len(shots), "planning")
        planned = plans(shot)
        if planned is None:
            unplanned += 1
        else:
            planned_shots.append(planned)
    progress(len(shots), len(shots), "planning")
    total = len(planned_shots) * len(CONDITIONS) * len(labels)
    done = 0
    for index, planned in enumerate(planned_shots):
        for condition in CONDITIONS:
            for label, controller in controllers_to_compare(robot):
                result = run_condition(robot, planned, controller, condition, seed=index)
                tallies[(condition, label)].record(result)
                done += 1
                progress(done, total, f"shot {index + 1}: {condition}")
    timing = timing_table(robot, planned_shots[0], repeats=1 if args.quick else 3)
    elapsed = time.perf_counter() - started
    lines = [
        "# Tracking pool strikes on Sawyer",
        "",
        f"Command: `python benchmarks/tracking.py --shots {args.shots}`",
        "",
        f"The first {args.shots} shots of the strike benchmark (seed {SEED}, {SPEED:g} m/s); "
        f"{len(planned_shots)} planned both ways ({unplanned} failed to plan and are left "
        f"out). Plans: `OptimalControl('time')` within {PLAN_MARGIN:.0%} of the velocity, "
        "acceleration and jerk limits, and on the full limits (the last condition). "
        "Dynamic plant (rigid-body dynamics, joint velocity servo, torques saturated), "
        f"{1 / DT:.0f} Hz. {elapsed:.0f} s in all.",
        "",
        *tracking_table(tallies, len(planned_shots), labels),
        "",
        "Medians over the runs, except the counts and the worst command. Tool error: the",
        "largest distance of the tool from its planned position. Strike errors, inside the",
        "strike phase: largest distance of the cue tip from the strike line, largest relative",
        "speed error along it, largest angle between the tip's velocity and the line. Runs",
        "over a limit: runs in which a command asked for a joint velocity beyond its limit.",
        *timing,
    ]
    write_report(lines, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
