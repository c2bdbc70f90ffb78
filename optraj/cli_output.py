"""The output file of ``optraj plan``: its format, rate and path, and the writing of it.

``--format json`` (the default) writes the exact trajectory that ``optraj check`` reads back;
``--format csv`` writes joint states at the fixed ``--rate`` (``Trajectory.to_csv``) and
``--format ros-yaml`` a ROS 2 ``trajectory_msgs/msg/JointTrajectory`` as YAML at that rate,
its efforts from the robot's inverse dynamics (``Trajectory.to_ros_yaml``). The options are
checked before anything is planned, and every error names its option.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, NamedTuple

from optraj.errors import InvalidInputError
from optraj.validation import as_choice, as_positive

__all__ = [
    "DEFAULT_RATE",
    "FORMATS",
    "OutputFile",
    "add_output_options",
    "output_file",
    "output_folder",
    "write_output",
]

#: The formats of ``--format`` and the suffix of each one's default file name.
FORMATS = {"json": ".json", "csv": ".csv", "ros-yaml": ".yaml"}
#: The rate of csv and ros-yaml when ``--rate`` is not given [Hz]: what joint trajectory
#: controllers commonly run at; each point is exact, the controller interpolates between.
DEFAULT_RATE = 100.0
#: The highest ``--rate`` [Hz]: one sample per microsecond (``planners.sampling.MAX_RATE``,
#: not imported here so that the command starts without the planners).
_MAX_RATE = 1e6


class OutputFile(NamedTuple):
    """Where and how ``optraj plan`` writes its trajectory.

    Attributes:
        path: The file to write.
        format: One of :data:`FORMATS`.
        rate: Sampling rate of csv and ros-yaml [Hz]; None for json (exact).
    """

    path: Path
    format: str
    rate: float | None


def add_output_options(plan: argparse.ArgumentParser) -> None:
    """Add ``--out``, ``--format`` and ``--rate`` to the ``optraj plan`` parser."""
    plan.add_argument(
        "--out",
        metavar="PATH",
        help="output file (default traj.json, traj.csv or traj.yaml, by --format)",
    )
    plan.add_argument(
        "--format",
        default="json",
        metavar="FORMAT",
        help="json: the exact trajectory, which 'optraj check' reads (default); csv: t, then "
        "q_, qd_, qdd_ of each joint [rad, rad/s, rad/s^2 or m, m/s, m/s^2] at --rate; "
        "ros-yaml: a ROS 2 trajectory_msgs/msg/JointTrajectory (with efforts [N m]) at --rate",
    )
    plan.add_argument(
        "--rate",
        type=float,
        metavar="HZ",
        help=f"sampling rate of csv and ros-yaml [Hz], in (0, 1e6] (default {DEFAULT_RATE:g})",
    )


def output_file(args: argparse.Namespace) -> OutputFile:
    """The output file that ``--out``, ``--format`` and ``--rate`` ask for, checked.

    Raises:
        UnknownNameError: A ``--format`` that is none of :data:`FORMATS`.
        InvalidInputError: A ``--rate`` that is not in (0, 1e6] Hz, or one given with
            ``--format json`` (whose output is exact, not sampled).
    """
    kind = as_choice(args.format, "--format", FORMATS)
    rate: float | None = None
    if args.rate is not None:
        if kind == "json":
            raise InvalidInputError(
                "--rate applies to --format csv and ros-yaml; --format json writes the exact "
                "trajectory, with no sampling rate",
                name="--rate",
            )
        rate = as_positive(args.rate, "--rate", "Hz", maximum=_MAX_RATE)
    elif kind != "json":
        rate = DEFAULT_RATE
    path = Path(args.out) if args.out is not None else Path("traj" + FORMATS[kind])
    return OutputFile(path, kind, rate)


def write_output(traj: Any, output: OutputFile, robot: Any) -> str:
    """Write ``traj`` (a ``planners.Trajectory``) as ``output`` asks; a sentence saying so.

    Args:
        traj: The planned trajectory.
        output: From :func:`output_file`.
        robot: The ``robots.Robot`` it was planned for (the efforts of ros-yaml).

    Raises:
        InvalidInputError: A path that cannot be written (a directory, a missing folder).
    """
    path = output.path
    if output.format == "json":
        traj.to_json(path)
        return f"Wrote {path}; check it again with: optraj check {path}"
    if output.format == "csv":
        traj.to_csv(path, rate=output.rate)
        rows = "t, q_, qd_ and qdd_ of each joint"
    else:
        traj.to_ros_yaml(path, rate=output.rate, robot=robot)
        rows = "a ROS 2 JointTrajectory with efforts"
    return f"Wrote {path} ({rows}, at {output.rate:g} Hz)"


def output_folder(folder: str | Path) -> Path:
    """``folder`` (the ``--out`` option), created with its parents if needed.

    Raises:
        InvalidInputError: The folder cannot be created (the message names ``--out``).
    """
    path = Path(folder)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InvalidInputError(
            f"cannot create the output folder {str(folder)!r}: {exc.strerror or exc}", name="out"
        ) from exc
    return path
