"""The joint states of a ROS 2 ``JointTrajectory`` dict, each field checked.

:func:`message_states` is what ``Trajectory.from_ros`` (:mod:`.ros_message`) builds a
trajectory from. Every refusal is a typed error naming where the message came from and the
field, as ``points[3].velocities``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.description import short_repr

__all__ = ["RosStates", "message_states"]

FloatArray = NDArray[np.float64]

#: The fields of a point that carry joint values; positions and velocities must be filled,
#: accelerations in every point or in none, effort is not read.
_FILLED = ("positions", "velocities")


class RosStates(NamedTuple):
    """The states of a message's points.

    Attributes:
        times: Times from the start [s], shape (m,).
        q: Positions [rad or m], shape (m, n).
        qd: Velocities [rad/s or m/s], shape (m, n).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (m, n), or None when no point has any.
        joint_names: The n joint names.
    """

    times: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray | None
    joint_names: tuple[str, ...]


def _field_error(where: str, field: str, detail: str) -> InvalidInputError:
    """The error for one field of a message from ``where`` (a file, or "message")."""
    return InvalidInputError(f"{where}: {field} {detail}", name=field)


def _values(point: Mapping[str, Any], key: str, field: str, n: int, where: str) -> list[float]:
    """The n finite numbers of ``point[key]``, or [] when it is missing or empty."""
    values = point.get(key, [])
    if values is None or (isinstance(values, list) and not values):
        return []
    if (
        not isinstance(values, list)
        or len(values) != n
        or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in values
        )
    ):
        raise _field_error(
            where, f"{field}.{key}", f"must be {n} finite numbers, got {short_repr(values)}"
        )
    return [float(v) for v in values]


def _seconds(point: Mapping[str, Any], field: str, where: str) -> float:
    """``time_from_start`` of a point [s]: ``{sec: int, nanosec: int in [0, 1e9)}``."""
    stamp = point.get("time_from_start")
    if (
        not isinstance(stamp, Mapping)
        or not all(type(stamp.get(key)) is int for key in ("sec", "nanosec"))
        or not 0 <= stamp["nanosec"] < 1_000_000_000
    ):
        raise _field_error(
            where,
            f"{field}.time_from_start",
            f"must be {{sec: int, nanosec: int in [0, 1e9)}}, got {short_repr(stamp)}",
        )
    return stamp["sec"] + stamp["nanosec"] * 1e-9


def _joint_names(data: Mapping[str, Any], where: str) -> tuple[str, ...]:
    """The message's joint names, at least one, each a str."""
    names = data.get("joint_names")
    if not isinstance(names, list) or not names or not all(isinstance(s, str) for s in names):
        raise _field_error(where, "joint_names", f"must be a list of str, got {short_repr(names)}")
    return tuple(names)


def _points(data: Mapping[str, Any], where: str) -> list[Mapping[str, Any]]:
    """The message's points: at least two mappings."""
    points = data.get("points")
    if not isinstance(points, list) or len(points) < 2:
        raise _field_error(
            where, "points", f"must be a list of at least 2 points, got {short_repr(points)}"
        )
    for k, point in enumerate(points):
        if not isinstance(point, Mapping):
            raise _field_error(where, f"points[{k}]", f"must be a mapping, got {short_repr(point)}")
    return points


def _check_times(times: FloatArray, where: str) -> None:
    """Refuse a first point not at 0 s or times that do not strictly increase."""
    if times[0] != 0.0:
        raise _field_error(
            where,
            "points[0].time_from_start",
            f"must be 0 s (an optraj trajectory starts at its first point), got {times[0]:.9g} s",
        )
    late = np.flatnonzero(np.diff(times) <= 0.0)
    if late.size:
        k = int(late[0]) + 1
        raise _field_error(
            where,
            f"points[{k}].time_from_start",
            f"{times[k]:.9g} s does not come after the point before ({times[k - 1]:.9g} s)",
        )


def _accelerations(rows: list[list[float]], where: str) -> FloatArray | None:
    """The points' accelerations, shape (m, n), or None when no point has any."""
    filled = [bool(row) for row in rows]
    if not any(filled):
        return None
    if not all(filled):
        k = filled.index(False)
        raise _field_error(
            where, f"points[{k}].accelerations", "are empty while other points have them"
        )
    return np.array(rows)


def message_states(data: object, where: str) -> RosStates:
    """The times and joint states of a ``JointTrajectory`` dict, every field checked.

    Args:
        data: The message as plain data (a dict, or what a YAML file held).
        where: Where it came from, for the messages: a quoted file name or ``"message"``.

    Raises:
        InvalidInputError: Not a mapping; no joint names or fewer than two points; a point
            without positions or velocities for every joint, with accelerations when another
            has none (or the other way round), or with a malformed ``time_from_start``; a
            first point not at 0 s or times that do not increase.
    """
    if not isinstance(data, Mapping):
        raise InvalidInputError(
            f"{where}: a JointTrajectory must be a mapping with joint_names and points, got "
            f"{short_repr(data)}",
            name="message",
        )
    names = _joint_names(data, where)
    points = _points(data, where)
    n = len(names)
    columns: dict[str, list[list[float]]] = {key: [] for key in (*_FILLED, "accelerations")}
    for k, point in enumerate(points):
        for key, rows in columns.items():
            values = _values(point, key, f"points[{k}]", n, where)
            if not values and key in _FILLED:
                raise _field_error(where, f"points[{k}].{key}", f"must hold {n} values, got none")
            rows.append(values)
    times = np.array([_seconds(p, f"points[{k}]", where) for k, p in enumerate(points)])
    _check_times(times, where)
    return RosStates(
        times,
        np.array(columns["positions"]),
        np.array(columns["velocities"]),
        _accelerations(columns["accelerations"], where),
        names,
    )
