"""The ``optraj`` command.

``optraj demo`` runs the main job: for now it loads every robot and prints its joints, limits
and tool pose at home. ``optraj robots`` lists the robots that can be loaded.
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
    return 0


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
