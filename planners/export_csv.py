"""A trajectory to and from CSV: joint states sampled at a fixed rate, one row per time.

``Trajectory.to_csv`` and ``Trajectory.from_csv`` are these functions. A file holds a header
row, then one row per time ``k / rate`` (k = 0, 1, ...) and the end time when it is off that
grid; no time is repeated, so it can be replayed by a controller running at ``rate``:

.. code-block:: text

    t,q_<joint 1>,...,q_<joint n>,qd_<joint 1>,...,qd_<joint n>,qdd_<joint 1>,...,qdd_<joint n>

in [s], [rad or m], [rad/s or m/s] and [rad/s^2 or m/s^2]. Numbers are written as the
shortest text that reads back to the same float.
"""

from __future__ import annotations

import csv
import io
import itertools
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.sampling import sampling_rate, uniform_times
from optraj.planners.serialization import (
    MAX_SAMPLED_BYTES,
    as_path,
    read_text_file,
    write_failure,
)

if TYPE_CHECKING:
    from optraj.planners.trajectory import Trajectory

__all__ = ["PREFIXES", "csv_header", "from_csv", "to_csv"]

FloatArray = NDArray[np.float64]

#: Column groups of a file, one column per joint each: positions, velocities, accelerations
#: (written), and the jerks that earlier files also held (read and ignored).
PREFIXES = ("q", "qd", "qdd", "jerk")
_WRITTEN = 3


def csv_header(joint_names: tuple[str, ...]) -> list[str]:
    """The header row: ``t``, then ``q_``, ``qd_`` and ``qdd_`` of each joint in turn."""
    return ["t"] + [f"{prefix}_{name}" for prefix in PREFIXES[:_WRITTEN] for name in joint_names]


def to_csv(trajectory: Trajectory, path: str | Path, rate: float = 1000.0) -> None:
    """Write the joint states at the fixed ``rate`` [Hz] to the CSV file ``path``.

    Rows at ``t = k / rate`` [s] for k = 0 .. floor(duration rate), plus the end time when
    ``duration rate`` is not a whole number: breakpoints are not added and no time is written
    twice. A jump at a breakpoint shows as a change between two rows (the checker, not the
    file, is where jumps are found). Columns: see :func:`csv_header`.

    Args:
        trajectory: The trajectory (``self`` when called as ``Trajectory.to_csv``).
        path: File to write [str or Path].
        rate: Sampling rate [Hz], in (0, MAX_RATE].

    Raises:
        InvalidInputError: A bad rate (see ``Trajectory.times``), or a path that is not a str
            or Path or cannot be written.
    """
    target = as_path(path)
    hz = sampling_rate(rate, trajectory.duration, trajectory.dof)
    sample = trajectory.sample(uniform_times(trajectory.duration, hz))
    table = np.column_stack([sample.t, sample.q, sample.qd, sample.qdd])
    try:
        with target.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(csv_header(trajectory.joint_names))
            writer.writerows(table.tolist())
    except OSError as exc:
        raise write_failure(target, exc) from exc


def from_csv(cls: type[Trajectory], path: str | Path) -> Trajectory:
    """Read a trajectory from a CSV file written by :func:`to_csv`.

    Between rows the trajectory is the quintic Hermite interpolant of the positions,
    velocities and accelerations of both rows: it passes through every row's state, is C2,
    and reproduces quintic segments exactly; where the original had a breakpoint between two
    rows the error is of the order of the jump in jerk times ``(1 / rate)^3``. (Cubic Hermite
    through positions and velocities alone, the other choice, leaves errors of order
    ``(1 / rate)^2`` and acceleration jumps at every row; it is used for files without
    ``qdd_`` columns.)

    Args:
        cls: The trajectory class (``Trajectory.from_csv``).
        path: The CSV file [str or Path]; the first time must be 0 s.

    Raises:
        InvalidInputError: No such file, or one that cannot be read; a header other than
            :func:`csv_header`'s, a row of another length, a value that is not a finite
            number, fewer than two rows or times that do not increase from 0. The message
            names the file, the row (the header is row 1) and the column.
    """
    source = as_path(path)
    rows = list(csv.reader(io.StringIO(read_text_file(source, MAX_SAMPLED_BYTES))))
    where = repr(str(source))
    while rows and not rows[-1]:  # blank lines at the end hold nothing
        rows.pop()
    if not rows:
        raise InvalidInputError(
            f"{where} is empty; expected the header t, q_<joint>..., qd_<joint>...",
            name="path",
        )
    names, groups = _layout(rows[0], where)
    table = _numbers(rows, where)
    _check_times(table[:, 0], where)
    n = len(names)
    q, qd, qdd = (table[:, 1 + g * n : 1 + (g + 1) * n] for g in range(3))
    return cls.from_hermite(table[:, 0], q, qd, qdd if groups >= 3 else None, joint_names=names)


def _cell_error(where: str, row: int, column: int, name: str, detail: str) -> InvalidInputError:
    """The error for one cell of a CSV file (row and column counted from 1, as editors do)."""
    return InvalidInputError(f"{where} row {row}, column {column} ({name}): {detail}", name="path")


def _layout(header: list[str], where: str) -> tuple[tuple[str, ...], int]:
    """The joint names and the number of column groups (2 to 4) of a header row."""
    leading = itertools.takewhile(lambda cell: cell.startswith("q_"), header[1:])
    names = tuple(cell[2:] for cell in leading)
    n = max(len(names), 1)
    groups = min(max((len(header) - 1) // n, 2), len(PREFIXES))
    expected = ["t"] + [f"{p}_{name}" for p in PREFIXES[:groups] for name in names]
    if not names:
        expected.append("q_<joint>")
    for column, (want, got) in enumerate(itertools.zip_longest(expected, header), start=1):
        if want != got:
            detail = (
                f"unexpected column {got!r} after the last joint group"
                if want is None
                else f"expected the header {want!r}, got {got!r}"
            )
            raise _cell_error(where, 1, column, got or "missing", detail)
    return names, groups


def _numbers(rows: list[list[str]], where: str) -> FloatArray:
    """The rows after the header as floats, shape (m, columns); every value finite."""
    header, body = rows[0], rows[1:]
    if len(body) < 2:
        raise InvalidInputError(
            f"{where} has {len(body)} rows of samples; a trajectory needs at least 2",
            name="path",
        )
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise InvalidInputError(
                f"{where} row {number} has {len(row)} values, the header {len(header)}",
                name="path",
            )
    try:
        table = np.array(body, dtype=float)
    except ValueError:
        table = None
    if table is not None and np.all(np.isfinite(table)):
        return table
    raise _first_bad_cell(rows, where)


def _first_bad_cell(rows: list[list[str]], where: str) -> InvalidInputError:
    """The error for the first value of a CSV file that is not a finite number."""
    for number, row in enumerate(rows[1:], start=2):
        for column, cell in enumerate(row, start=1):
            try:
                finite = math.isfinite(float(cell))
            except ValueError:
                finite = False
            if not finite:
                return _cell_error(
                    where, number, column, rows[0][column - 1], f"{cell!r} is not a finite number"
                )
    return InvalidInputError(f"{where} holds a value that is not a number", name="path")


def _check_times(times: FloatArray, where: str) -> None:
    """Refuse times that do not start at 0 or do not strictly increase (rows from 2)."""
    if times[0] != 0.0:
        raise _cell_error(where, 2, 1, "t", f"the first time must be 0 s, got {times[0]:.9g} s")
    steps = np.diff(times)
    if np.any(steps <= 0.0):
        k = int(np.argmax(steps <= 0.0))
        raise _cell_error(
            where,
            k + 3,
            1,
            "t",
            f"time {times[k + 1]:.9g} s does not come after {times[k]:.9g} s of the row before",
        )
