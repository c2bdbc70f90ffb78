"""A trajectory as a ROS 2 ``trajectory_msgs/msg/JointTrajectory``, as a dict or YAML, and back.

``Trajectory.to_ros``, ``Trajectory.to_ros_yaml`` and ``Trajectory.from_ros`` are these
functions; no ROS installation is needed. The dict has the message's fields, nested as the
message nests them (``std_msgs/msg/Header``, ``builtin_interfaces/msg/Time`` and ``Duration``):

.. code-block:: text

    header: {stamp: {sec, nanosec}, frame_id}
    joint_names: [...]
    points:
      - {positions, velocities, accelerations, effort, time_from_start: {sec, nanosec}}

so that it converts to the message with ``rosidl_runtime_py.set_message_fields`` and its YAML
is what ``ros2 topic pub`` and ``ros2 topic echo`` read and write. A zero stamp means "start
when received", as ``joint_trajectory_controller`` takes it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.description import as_joint_names, short_repr
from optraj.planners.ros_reading import message_states
from optraj.planners.sampling import sampling_rate, uniform_times
from optraj.planners.serialization import (
    MAX_SAMPLED_BYTES,
    as_path,
    read_text_file,
    write_text,
)

if TYPE_CHECKING:
    from optraj.planners.trajectory import Trajectory
    from optraj.robots import Robot

__all__ = ["from_ros", "ros_points", "to_ros", "to_ros_yaml"]

FloatArray = NDArray[np.float64]

#: libyaml's dumper and loader when PyYAML was built with it (several times faster).
_DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _time_field(t: float) -> dict[str, int]:
    """A ``builtin_interfaces`` time or duration: whole seconds and nanoseconds in [0, 1e9)."""
    sec, nanosec = divmod(round(t * 1e9), 1_000_000_000)
    return {"sec": int(sec), "nanosec": int(nanosec)}


def _names(
    trajectory: Trajectory, robot: Robot | None, joint_names: Sequence[str] | None
) -> tuple[str, ...]:
    """The joint names of the message: those given, else the robot's, else the trajectory's."""
    if joint_names is not None:
        return as_joint_names(joint_names, trajectory.dof)
    return robot.joint_names if robot is not None else trajectory.joint_names


def _checked_robot(trajectory: Trajectory, robot: object) -> Robot | None:
    """The robot whose inverse dynamics gives the efforts, checked against the trajectory."""
    from optraj.robots import Robot

    if robot is None:
        return None
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {short_repr(robot)}", name="robot"
        )
    if robot.dof != trajectory.dof:
        raise InvalidInputError(
            f"robot {robot.name!r} has {robot.dof} joints, the trajectory {trajectory.dof}",
            name="robot",
        )
    return robot


def ros_points(trajectory: Trajectory, rate: float | None) -> FloatArray:
    """The times [s] of the message's points: the breakpoints, or ``to_csv``'s fixed rate."""
    if rate is None:
        return trajectory.breakpoints
    hz = sampling_rate(rate, trajectory.duration, trajectory.dof)
    return uniform_times(trajectory.duration, hz)


def to_ros(
    trajectory: Trajectory,
    rate: float | None = None,
    *,
    robot: Robot | None = None,
    joint_names: Sequence[str] | None = None,
) -> dict[str, Any]:
    """The trajectory as a ROS 2 ``trajectory_msgs/msg/JointTrajectory`` dict (plain data).

    Args:
        trajectory: The trajectory (``self`` when called as ``Trajectory.to_ros``).
        rate: Point rate [Hz]: the times of :func:`~optraj.planners.export_csv.to_csv` at this
            rate (so that the two exports agree). ``None`` puts one point at each breakpoint
            (right-hand values at a jump): exact for a controller that interpolates quintic
            splines between points when the trajectory is C2 and of degree <= 5, lossy
            otherwise (LSPB, TOPPRA: give a rate).
        robot: When given, ``effort`` holds its inverse dynamics (RNEA, gravity included)
            [N m or N] along the motion; otherwise ``effort`` is empty, as ROS leaves it.
        joint_names: Names for the message; the robot's, else the trajectory's when None.

    Returns:
        ``{"header": {"stamp": {"sec", "nanosec"}, "frame_id": ""}, "joint_names": [...],
        "points": [{"positions", "velocities", "accelerations", "effort",
        "time_from_start": {"sec", "nanosec"}}, ...]}``, lists of floats [rad, rad/s, rad/s^2
        or m, m/s, m/s^2] in joint order.

    Raises:
        InvalidInputError: A bad rate (see ``Trajectory.times``), a robot that is not a
            ``robots.Robot`` or has another number of joints, or joint names that do not fit.
    """
    model = _checked_robot(trajectory, robot)
    names = _names(trajectory, model, joint_names)
    sample = trajectory.sample(ros_points(trajectory, rate))
    efforts = model.inverse_dynamics(sample.q, sample.qd, sample.qdd).tolist() if model else None
    points = [
        {
            "positions": sample.q[k].tolist(),
            "velocities": sample.qd[k].tolist(),
            "accelerations": sample.qdd[k].tolist(),
            "effort": efforts[k] if efforts is not None else [],
            "time_from_start": _time_field(float(t)),
        }
        for k, t in enumerate(np.atleast_1d(sample.t))
    ]
    return {
        "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
        "joint_names": list(names),
        "points": points,
    }


def to_ros_yaml(
    trajectory: Trajectory,
    path: str | Path | None = None,
    rate: float | None = None,
    *,
    robot: Robot | None = None,
    joint_names: Sequence[str] | None = None,
) -> str:
    """The :func:`to_ros` message as YAML text; also written to ``path`` when given.

    Args:
        trajectory: The trajectory (``self`` when called as ``Trajectory.to_ros_yaml``).
        path: File to write [str or Path], or None.
        rate: As for :func:`to_ros` [Hz].
        robot: As for :func:`to_ros`.
        joint_names: As for :func:`to_ros`.

    Raises:
        InvalidInputError: As for :func:`to_ros`, or a path that is not a str or Path or
            cannot be written.
    """
    if path is not None:
        as_path(path)  # a bad path is refused before any sampling
    message = to_ros(trajectory, rate, robot=robot, joint_names=joint_names)
    text = yaml.dump(message, Dumper=_DUMPER, sort_keys=False, default_flow_style=None)
    if path is not None:
        write_text(path, text)
    return text


def from_ros(cls: type[Trajectory], message: Mapping[str, Any] | str | Path) -> Trajectory:
    """Read a trajectory from a ``JointTrajectory`` dict or a YAML file of one.

    Between points the trajectory is the quintic Hermite interpolant of the positions,
    velocities and accelerations (what ``joint_trajectory_controller`` does with them); cubic
    when the points have no accelerations. The efforts and the header are not kept.

    Args:
        cls: The trajectory class (``Trajectory.from_ros``).
        message: A dict as :func:`to_ros` returns, or the path of a YAML file of one
            (:func:`to_ros_yaml`).

    Raises:
        InvalidInputError: No such file, one that cannot be read or is not YAML; a message
            without joint names or points, a point of the wrong size or without velocities,
            fewer than two points, a first point not at 0 s or times that do not increase.
            The message names the file and the field (``points[3].velocities``).
    """
    data: object = message
    where = "message"
    if not isinstance(message, Mapping):
        source = as_path(message, "message")
        where = repr(str(source))
        try:
            data = yaml.load(read_text_file(source, MAX_SAMPLED_BYTES), Loader=_LOADER)
        except yaml.YAMLError as exc:
            raise InvalidInputError(
                f"{where} is not YAML: {exc}".replace("\n", " "), name="message"
            ) from exc
    states = message_states(data, where)
    return cls.from_hermite(
        states.times, states.q, states.qd, states.qdd, joint_names=states.joint_names
    )
