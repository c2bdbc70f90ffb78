"""The ``optraj`` command.

``optraj demo`` runs the main job: it loads every robot and prints its joints, limits and tool
pose at home, reproduces the ECE486 seed's paddle table, and shows the independent checker's
verdict on classic plans. ``optraj robots`` lists the robots that can be loaded.
Errors print one line to stderr and exit with status 2; the packages are imported lazily so
that ``optraj --help`` is instant.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import TextIO

from optraj.errors import MissingDependencyError, OptrajError

__all__ = ["main"]


def _robot_report(name: str, out: TextIO) -> None:
    import numpy as np
    import pinocchio as pin

    import robots

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


def _cmd_demo(args: argparse.Namespace, out: TextIO) -> int:
    import robots

    out.write("optraj robots: joints, limits (units per row) and the tool pose at home\n")
    missing = []
    for name in robots.known_robots():
        try:
            _robot_report(name, out)
        except MissingDependencyError as exc:
            if not args.skip_missing:
                raise
            missing.append(f"{name} ({exc})")
    for line in missing:
        out.write(f"\nskipped {line}\n")
    _seed_table(out)
    _verdicts(out)
    return 0


def _seed_table(out: TextIO) -> None:
    import numpy as np

    import planners
    import problems

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
    import planners
    import problems

    cases = [
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
            note = ", ".join(
                f"{f.name} {'unbounded (jump)' if f.ratio == float('inf') else f'{f.ratio:.0%}'}"
                for f in report.violations
            )
        else:
            note = "+".join(q[:3] for q in (quantities or planners.checker.QUANTITIES)) + ", task"
        verdict = "ok" if report.ok else "FAIL"
        out.write(f"  {task:<24}{planner.name:<30}{traj.duration:>9.3f}  {verdict:<8}{note}\n")


def _cmd_robots(args: argparse.Namespace, out: TextIO) -> int:
    import robots

    for name, summary in robots.known_robots().items():
        out.write(f"{name:<10}{summary}\n")
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="optraj",
        description=(
            "Optimization-based motion planning for arms that strike and carry. Units: m, rad, "
            "s, rad/s, rad/s^2, rad/s^3, N m (N for prismatic joints)."
        ),
    )
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run the main job: load every robot and print a table")
    demo.add_argument(
        "--strict",
        dest="skip_missing",
        action="store_false",
        help="fail instead of skipping robots whose optional package is missing",
    )
    demo.set_defaults(run=_cmd_demo)
    listing = sub.add_parser("robots", help="list the robots that robots.load() knows")
    listing.set_defaults(run=_cmd_robots)
    return parser


def main(argv: Sequence[str] | None = None, out: TextIO | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 bad input or failure)."""
    args = _parser().parse_args(argv)
    stream = out if out is not None else sys.stdout
    try:
        return int(args.run(args, stream))
    except OptrajError as exc:
        print(f"optraj: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
