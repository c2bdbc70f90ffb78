"""``optraj robots [NAME ...]``: the robots ``robots.load`` knows, or their joints and limits.

Without a name it lists the robots, one line each. With names it prints each robot's joints
with their limits (position, velocity, acceleration, jerk and effort, units per row), the named
poses, and the tool frame's pose at home.
"""

from __future__ import annotations

import argparse
from typing import Any, TextIO

__all__ = ["add_robots_parser", "cmd_robots", "robot_table"]


def robot_table(name: str, out: TextIO) -> None:
    """Print one robot's joints, limits, named poses and tool pose at home.

    Raises:
        UnknownNameError: An unknown robot (lists the known ones).
        MissingDependencyError: A robot whose optional package is not installed.
    """
    import numpy as np
    import pinocchio as pin

    from optraj import robots

    robot = robots.load(name)
    T = robot.tool_pose(robot.home)
    rpy = pin.rpy.matrixToRpy(T[:3, :3])
    out.write(f"{robot.name}: {robot.description}\n")
    width = max(len(joint) for joint in ("joint", *robot.joint_names)) + 2
    out.write(
        f"  {'joint':<{width}}{'unit':>5}{'lower':>10}{'upper':>10}{'home':>10}"
        f"{'vel':>9}{'acc':>9}{'jerk':>9}{'effort':>9}\n"
    )
    for row, q in zip(robot.limits.table(), robot.home, strict=True):
        out.write(
            f"  {row['joint']:<{width}}{row['unit']:>5}{row['lower']:>10.4f}{row['upper']:>10.4f}"
            f"{q:>10.4f}{row['velocity']:>9.3f}{row['acceleration']:>9.2f}{row['jerk']:>9.1f}"
            f"{row['effort']:>9.2f}\n"
        )
    out.write(
        "  units: unit [rad or m], vel per s, acc per s^2, jerk per s^3, effort [N m or N]\n"
        f"  poses: {_poses(robot)}\n"
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


def _poses(robot: Any) -> str:
    """The named poses, saying which only rename home (Sawyer's ``neutral`` is its home)."""
    import numpy as np

    return ", ".join(
        f"{name} (= home)" if name != "home" and np.array_equal(q, robot.home) else name
        for name, q in robot.poses.items()
    )


def cmd_robots(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``optraj robots``: the list, or each named robot's table; exit 0."""
    from optraj import robots

    if not args.names:
        for name, summary in robots.known_robots().items():
            out.write(f"{name:<10}{summary}\n")
        out.write("joints and limits of one: optraj robots NAME\n")
        return 0
    for index, name in enumerate(args.names):
        if index:
            out.write("\n")
        robot_table(name.lower(), out)
    return 0


def add_robots_parser(sub: Any) -> None:
    """Add the ``robots`` command to the subparsers ``sub`` of the ``optraj`` parser."""
    parser = sub.add_parser(
        "robots",
        help="list the robots that robots.load() knows, or show their joints and limits",
        description=(
            "Without NAME, list the robots that robots.load() knows. With names, print each "
            "one's joints and limits: position [rad or m], velocity [rad/s or m/s], "
            "acceleration [rad/s^2], jerk [rad/s^3], effort [N m or N], its named poses and "
            "its tool frame's pose at home (position [m], roll-pitch-yaw [deg])."
        ),
    )
    parser.add_argument("names", nargs="*", metavar="NAME", help="robot names")
    parser.set_defaults(run=cmd_robots)
