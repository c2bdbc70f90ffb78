"""A trajectory to and from exact JSON, and the file handling of every trajectory format.

The :class:`~optraj.planners.trajectory.Trajectory` methods ``to_dict``, ``from_dict``,
``to_json`` and ``from_json`` are the faces of these functions; call those. The JSON form
(:data:`FORMAT`, its schema in :mod:`.trajectory_schema`) keeps the polynomials exactly, so a
trajectory read back samples to the same numbers; metadata values without a JSON form are left
out. :func:`as_path`, :func:`write_text` and :func:`read_text_file` are shared with the
sampled formats (:mod:`.export_csv`, :mod:`.ros_message`).
"""

from __future__ import annotations

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
    "MAX_SAMPLED_BYTES",
    "as_path",
    "from_dict",
    "is_json_text",
    "read_json",
    "read_text_file",
    "to_json",
    "trajectory_arguments",
    "trajectory_dict",
    "write_failure",
    "write_text",
]

#: The ``format`` field of every trajectory JSON file.
FORMAT = "optraj.trajectory/1"
#: Deepest nesting of lists and objects in a file's metadata: ours are two levels deep
#: (``problem_options`` with a list), and the exports recurse through them.
MAX_METADATA_DEPTH = 32
#: Largest sampled trajectory file read (CSV, ROS YAML) [bytes]: 1e7 sampled values, the most
#: any sampling holds (:data:`optraj.validation.MAX_COUNT`), take about 220 MB of CSV.
MAX_SAMPLED_BYTES = 256 * 2**20


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


def as_path(path: object, name: str = "path") -> Path:
    """``path`` as a Path, or a typed error for something that is not a file path.

    Raises:
        InvalidInputError: Not a str or a Path (the message names the argument ``name``).
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidInputError(
            f"{name} must be a str or a Path, got {short_repr(path)}", name=name
        )
    return Path(path)


def write_failure(path: Path, exc: OSError) -> InvalidInputError:
    """A typed error for a file that cannot be written (a directory, no permission, ...)."""
    reason = exc.strerror or str(exc)
    return InvalidInputError(f"cannot write {str(path)!r}: {reason}", name="path", value=path)


def write_text(path: object, text: str) -> None:
    """Write ``text`` to the file ``path`` (a str or a Path).

    Raises:
        InvalidInputError: A path that is not a str or Path, or that cannot be written (a
            directory, a missing folder, no permission).
    """
    target = as_path(path)
    try:
        target.write_text(text)
    except OSError as exc:
        raise write_failure(target, exc) from exc


def trajectory_dict(trajectory: Trajectory) -> dict[str, Any]:
    """The exact trajectory as plain JSON-ready data (metadata without non-JSON values).

    ``Trajectory.to_dict``; the data follows the schema of :mod:`.trajectory_schema`.
    """
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


def from_dict(cls: type[Trajectory], data: Mapping[str, Any]) -> Trajectory:
    """Rebuild a trajectory from :func:`trajectory_dict` output (``Trajectory.from_dict``).

    Raises:
        InvalidInputError: Another format, or a missing or malformed field (each field is
            checked as the constructor checks its argument).
    """
    return cls(**trajectory_arguments(data))


def to_json(trajectory: Trajectory, path: str | Path | None = None) -> str:
    """The exact trajectory as JSON text; also written to ``path`` when given.

    ``Trajectory.to_json``.

    Raises:
        InvalidInputError: A path that is not a str or Path, or that cannot be written (a
            directory, a missing folder, no permission).
    """
    text = json.dumps(trajectory_dict(trajectory), indent=1)
    if path is not None:
        write_text(path, text)
    return text


def read_text_file(path: Path, max_bytes: int) -> str:
    """The text of a trajectory file of at most ``max_bytes`` bytes.

    Raises:
        InvalidInputError: No such file, one over ``max_bytes``, or one that cannot be read
            or is not UTF-8 text; the message names the file.
    """
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


def is_json_text(source: object) -> bool:
    """Whether ``source`` is JSON text (a str starting with ``{``) rather than a file path."""
    return isinstance(source, str) and source.lstrip().startswith("{")


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
    if not is_json_text(source):
        path = Path(source)
        where = f" in {str(path)!r}"
        text = read_text_file(path, max_bytes)
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
