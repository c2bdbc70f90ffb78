"""A trajectory to and from files: exact JSON, sampled CSV, ROS ``JointTrajectory`` dicts.

The :class:`~optraj.planners.trajectory.Trajectory` methods ``to_dict``, ``from_dict``,
``to_json``, ``from_json``, ``to_csv`` and ``to_ros`` are the faces of these functions; call
those. The JSON form (:data:`FORMAT`) keeps the polynomials exactly, so a trajectory read back
samples to the same numbers; metadata values without a JSON form are left out.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.description import short_repr
from optraj.planners.phase import Phase

if TYPE_CHECKING:
    from optraj.planners.trajectory import Trajectory

__all__ = [
    "FORMAT",
    "MAX_METADATA_DEPTH",
    "read_json",
    "ros_message",
    "trajectory_arguments",
    "trajectory_dict",
    "write_csv",
    "write_text",
]

#: The ``format`` field of every trajectory JSON file.
FORMAT = "optraj.trajectory/1"
#: Deepest nesting of lists and objects in a file's metadata: ours are two levels deep
#: (``problem_options`` with a list), and the exports recurse through them.
MAX_METADATA_DEPTH = 32


def _jsonable(value: Any) -> Any:
    """A metadata value as plain JSON data, or ``None`` when it has no JSON form.

    Non-finite floats become their str (``"inf"``), NumPy scalars and arrays plain numbers
    and lists, mappings and sequences are converted item by item.
    """
    if isinstance(value, (str, bool, int)) or value is None:
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else str(value)
    if isinstance(value, np.generic):
        return _jsonable(value.item())
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()] if value.dtype != object else None
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return None


def _nesting_depth(value: object) -> int:
    """How deeply lists, tuples and mappings nest in ``value`` (0 for a scalar).

    Walked with a stack, not recursion, so that any depth is measured.
    """
    deepest = 0
    stack = [(value, 0)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, Mapping):
            children: Iterable[object] = item.values()
        elif isinstance(item, (list, tuple)):
            children = item
        else:
            continue
        deepest = max(deepest, level + 1)
        stack.extend((child, level + 1) for child in children)
    return deepest


def _writable(path: object) -> Path:
    """``path`` as a Path, or a typed error for something that is not a file path."""
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidInputError(
            f"path must be a str or a Path, got {short_repr(path)}", name="path"
        )
    return Path(path)


def _write_error(path: Path, exc: OSError) -> InvalidInputError:
    """A typed error for a file that cannot be written (a directory, no permission, ...)."""
    reason = exc.strerror or str(exc)
    return InvalidInputError(f"cannot write {str(path)!r}: {reason}", name="path", value=path)


def write_text(path: object, text: str) -> None:
    """Write ``text`` to the file ``path`` (a str or a Path).

    Raises:
        InvalidInputError: A path that is not a str or Path, or that cannot be written (a
            directory, a missing folder, no permission).
    """
    target = _writable(path)
    try:
        target.write_text(text)
    except OSError as exc:
        raise _write_error(target, exc) from exc


def trajectory_dict(trajectory: Trajectory) -> dict[str, Any]:
    """The exact trajectory as plain JSON-ready data (metadata without non-JSON values)."""
    metadata = {k: _jsonable(v) for k, v in trajectory.metadata.items()}
    return {
        "format": FORMAT,
        "joint_names": list(trajectory.joint_names),
        "breakpoints": trajectory.breakpoints.tolist(),
        "coefficients": trajectory.coefficients.tolist(),
        "phases": [
            {"name": p.name, "t_start": p.t_start, "t_end": p.t_end} for p in trajectory.phases
        ],
        "metadata": {k: v for k, v in metadata.items() if v is not None},
    }


def _malformed(field: str, detail: str) -> InvalidInputError:
    """The error for a missing or malformed field of trajectory data."""
    return InvalidInputError(
        f"trajectory data is missing or has a malformed field: {detail}", name=field
    )


def trajectory_arguments(data: Mapping[str, Any]) -> dict[str, Any]:
    """The constructor arguments of the trajectory that :func:`trajectory_dict` gave ``data``.

    Only the layout is checked here; the constructor checks each value.

    Raises:
        InvalidInputError: Another format, a missing field, phases that are not a list of
            ``{name, t_start, t_end}`` objects, or metadata that is not an object nested at
            most :data:`MAX_METADATA_DEPTH` levels deep.
    """
    if not isinstance(data, Mapping) or data.get("format") != FORMAT:
        found = data.get("format") if isinstance(data, Mapping) else type(data).__name__
        raise InvalidInputError(
            f"not an optraj trajectory: expected format {FORMAT!r}, got {found!r}",
            name="data",
        )
    missing = [key for key in ("breakpoints", "coefficients", "phases") if key not in data]
    if missing:
        raise _malformed("data", f"no {', '.join(missing)}")
    rows = data["phases"]
    if not isinstance(rows, list) or not all(
        isinstance(row, Mapping) and {"name", "t_start", "t_end"} <= row.keys() for row in rows
    ):
        raise _malformed(
            "phases",
            f"phases must be a list of {{name, t_start, t_end}} objects, got {short_repr(rows)}",
        )
    metadata = data.get("metadata", {})
    if not isinstance(metadata, Mapping) or _nesting_depth(metadata) > MAX_METADATA_DEPTH:
        raise _malformed(
            "metadata",
            f"metadata must be an object nested at most {MAX_METADATA_DEPTH} levels deep, got "
            f"{short_repr(metadata)}",
        )
    return {
        "breakpoints": data["breakpoints"],
        "coefficients": data["coefficients"],
        "joint_names": data.get("joint_names"),
        "phases": [Phase(row["name"], row["t_start"], row["t_end"]) for row in rows],
        "metadata": metadata,
    }


def _read_file(path: Path, max_bytes: int) -> str:
    """The text of a trajectory file of at most ``max_bytes`` bytes."""
    if not path.is_file():
        raise InvalidInputError(f"no trajectory file at {str(path)!r}", name="source")
    try:
        size = path.stat().st_size
        if size > max_bytes:
            raise InvalidInputError(
                f"{str(path)!r} has {size} bytes, more than the {max_bytes} bytes "
                "of any trajectory file",
                name="source",
            )
        return path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8 text"
        raise InvalidInputError(f"cannot read {str(path)!r}: {reason}", name="source") from exc


def read_json(source: str | Path, max_bytes: int) -> Any:
    """The JSON data of ``source``: JSON text (it starts with ``{``) or a file path.

    Args:
        source: JSON text, or the path of a JSON file.
        max_bytes: Longest text or file accepted [bytes, or characters for text].

    Raises:
        InvalidInputError: Neither a str nor a path, no such file, one that cannot be read,
            text over ``max_bytes``, or not valid JSON (nested too deeply, a number too long).
    """
    if not isinstance(source, (str, os.PathLike)):
        raise InvalidInputError(
            f"source must be JSON text or a file path, got {short_repr(source)}", name="source"
        )
    text = str(source)
    where = ""  # the file, for the messages
    if not text.lstrip().startswith("{"):
        path = Path(source)
        where = f" in {str(path)!r}"
        text = _read_file(path, max_bytes)
    elif len(text) > max_bytes:
        raise InvalidInputError(
            f"trajectory JSON has {len(text)} characters, more than the {max_bytes} "
            "of any trajectory file",
            name="source",
        )
    try:
        return json.loads(text)
    except RecursionError as exc:
        raise InvalidInputError(
            f"trajectory JSON is malformed{where}: nested too deeply", name="source"
        ) from exc
    except ValueError as exc:  # JSONDecodeError, and integers of over 4300 digits
        raise InvalidInputError(
            f"trajectory JSON is malformed{where}: {exc}", name="source"
        ) from exc


def write_csv(trajectory: Trajectory, path: object, rate: float) -> None:
    """Write samples at ``rate`` [Hz] to ``path``: columns t, q_<joint>, qd_, qdd_, jerk_.

    Raises:
        InvalidInputError: A bad rate, or a path that is not a str or Path or cannot be
            written.
    """
    target = _writable(path)
    arrays = trajectory.to_arrays(rate)
    header = ["t"] + [
        f"{prefix}_{name}"
        for prefix in ("q", "qd", "qdd", "jerk")
        for name in trajectory.joint_names
    ]
    table = np.column_stack([arrays[key] for key in ("t", "q", "qd", "qdd", "jerk")])
    try:
        with target.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(header)
            writer.writerows(table.tolist())
    except OSError as exc:
        raise _write_error(target, exc) from exc


def ros_message(trajectory: Trajectory, rate: float | None) -> dict[str, Any]:
    """A dict shaped like ROS ``trajectory_msgs/JointTrajectory``: see ``Trajectory.to_ros``."""
    if rate is None:
        times = trajectory.breakpoints
    else:
        times = trajectory.times(rate, include_breakpoints=False)
    sample = trajectory.sample(times)
    points = []
    for k, t in enumerate(np.atleast_1d(sample.t)):
        sec, nanosec = divmod(round(float(t) * 1e9), 1_000_000_000)
        points.append(
            {
                "positions": sample.q[k].tolist(),
                "velocities": sample.qd[k].tolist(),
                "accelerations": sample.qdd[k].tolist(),
                "time_from_start": {"sec": sec, "nanosec": nanosec},
            }
        )
    return {"joint_names": list(trajectory.joint_names), "points": points}
