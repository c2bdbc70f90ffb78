"""Sweep rows arranged as maps over the table: one value per ball position, per heading.

:func:`heading_maps` picks the rows of one speed (or all), groups them by heading and ball
position, and gives each heading a :class:`HeadingMap`: on a regular x/y grid (every
combination of the rows' x and y present) a 2-D array of cells, otherwise the scattered
points of a random set. A cell or point whose rows give no value (a refused or failed shot)
is NaN. The drawing is :mod:`optraj.sweeps.plot`'s.

>>> maps = heading_maps(rows, "motion_time", speed=0.5)   # doctest: +SKIP
>>> maps[0].heading, maps[0].values.shape                 # doctest: +SKIP
(0.0, (20, 20))
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.validation import as_number

__all__ = ["MAX_PANELS", "SPEED_TOLERANCE", "HeadingMap", "heading_maps", "rows_of", "speeds_of"]

FloatArray = NDArray[np.float64]

#: Most headings drawn one panel each; rows with more (a random set) share one panel.
MAX_PANELS = 8
#: Two speeds this close are the same [m/s] (shot ids round speeds to 0.1 mm/s).
SPEED_TOLERANCE = 5e-5
#: Two headings this close are the same [deg] (shot ids round them to 1e-3 deg).
HEADING_TOLERANCE = 5e-4
#: The columns every map needs.
NEEDED = ("ball_x", "ball_y", "heading", "speed", "status")


@dataclass(frozen=True)
class HeadingMap:
    """The values of one column over the ball positions, for one heading.

    Attributes:
        heading: Shot direction [deg], or None when the panel holds every heading.
        x: On a grid, the cells' ball x [m] ascending, shape (nx,); else each point's x, (k,).
        y: On a grid, the cells' ball y [m] ascending, shape (ny,); else each point's y, (k,).
        values: On a grid, shape (ny, nx), ``values[j, i]`` at ``(x[i], y[j])``; else (k,).
            NaN where the rows give no value.
        on_grid: Whether the rows cover a regular grid.
    """

    heading: float | None
    x: FloatArray
    y: FloatArray
    values: FloatArray
    on_grid: bool


def _number(value: object) -> float | None:
    """A float, or None for None, NaN and anything that is not a number."""
    if value is None or isinstance(value, (bool, str)):
        return None
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    return None if math.isnan(number) else number


def rows_of(data: Any) -> list[dict[str, object]]:
    """The rows of a sweep given as an iterable of dicts or as a pandas DataFrame.

    Raises:
        InvalidInputError: No rows, a row that is not a mapping, or one of the columns every
            map needs (ball_x, ball_y, heading, speed, status) missing.
    """
    if hasattr(data, "to_dict") and hasattr(data, "columns"):
        data = data.to_dict("records")
    if isinstance(data, (str, bytes, Mapping)) or not isinstance(data, Iterable):
        raise InvalidInputError(
            f"rows must be sweep rows (dicts) or a DataFrame, got {type(data).__name__}",
            name="rows",
        )
    rows = list(data)
    if not rows:
        raise InvalidInputError("rows must hold at least one sweep row, got none", name="rows")
    for index, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise InvalidInputError(
                f"rows[{index}] must be a dict of columns, got {type(row).__name__}", name="rows"
            )
        missing = [name for name in NEEDED if name not in row]
        if missing:
            raise InvalidInputError(
                f"rows[{index}] lacks the column {missing[0]!r}; a map needs {', '.join(NEEDED)}",
                name="rows",
                value=missing[0],
            )
        for name in NEEDED[:4]:
            if _number(row[name]) is None:
                raise InvalidInputError(
                    f"rows[{index}][{name!r}] must be a number, got {row[name]!r}",
                    name="rows",
                    value=row[name],
                )
    return [dict(row) for row in rows]


def speeds_of(rows: Iterable[Mapping[str, object]]) -> list[float]:
    """The distinct speeds of ``rows`` [m/s], ascending."""
    found: list[float] = []
    for value in sorted(v for v in (_number(row["speed"]) for row in rows) if v is not None):
        if not found or value - found[-1] > SPEED_TOLERANCE:
            found.append(value)
    return found


def _listed(values: list[float], unit: str) -> str:
    shown = ", ".join(f"{value:.6g}" for value in values[:10])
    return f"{shown}{', ...' if len(values) > 10 else ''} {unit}"


def _at_speed(rows: list[dict[str, object]], speed: float | None) -> list[dict[str, object]]:
    if speed is None:
        return rows
    wanted = as_number(speed, "speed", "m/s", minimum=0.0, open_minimum=True)
    chosen = [
        row for row in rows if abs((_number(row["speed"]) or math.inf) - wanted) <= SPEED_TOLERANCE
    ]
    if not chosen:
        raise InvalidInputError(
            f"speed {wanted:.6g} m/s is not in the rows; their speeds: "
            f"{_listed(speeds_of(rows), 'm/s')}",
            name="speed",
            value=speed,
        )
    return chosen


def _headings(rows: list[dict[str, object]], wanted: Iterable[float] | None) -> list[float | None]:
    """The headings to draw a panel each (None: one panel of every heading)."""
    known: list[float] = []
    for value in sorted({round(_number(row["heading"]) or 0.0, 3) for row in rows}):
        if not known or value - known[-1] > HEADING_TOLERANCE:
            known.append(value)
    if wanted is None:
        return list(known) if len(known) <= MAX_PANELS else [None]
    chosen: list[float | None] = []
    for heading in wanted:
        number = as_number(heading, "heading", "deg")
        if not any(abs(number - k) <= HEADING_TOLERANCE for k in known):
            raise InvalidInputError(
                f"heading {number:.6g} deg is not in the rows; their headings: "
                f"{_listed(known, 'deg')}",
                name="headings",
                value=heading,
            )
        chosen.append(number)
    if not chosen:
        raise InvalidInputError(
            "headings must name at least one heading, got none", name="headings"
        )
    return chosen


def _points(
    rows: list[dict[str, object]], column: str, one_per_point: bool
) -> dict[tuple[float, float], float]:
    """The value at each ball position (x, y) [m]: the largest of its rows', else NaN.

    With ``one_per_point``, several speeds at one position are refused.
    """
    values: dict[tuple[float, float], list[float]] = {}
    speeds: dict[tuple[float, float], float] = {}
    for row in rows:
        key = (round(_number(row["ball_x"]) or 0.0, 4), round(_number(row["ball_y"]) or 0.0, 4))
        speed = _number(row["speed"]) or 0.0
        if one_per_point and abs(speeds.setdefault(key, speed) - speed) > SPEED_TOLERANCE:
            raise InvalidInputError(
                f"the rows hold several speeds ({_listed(speeds_of(rows), 'm/s')}) at one ball "
                "position: choose one with speed=",
                name="speed",
            )
        value = _number(row.get(column))
        values.setdefault(key, [])
        if value is not None:
            values[key].append(value)
    return {key: max(found) if found else math.nan for key, found in values.items()}


def _one_map(heading: float | None, points: dict[tuple[float, float], float]) -> HeadingMap:
    xs = sorted({x for x, _ in points})
    ys = sorted({y for _, y in points})
    if len(xs) * len(ys) == len(points):
        values = np.full((len(ys), len(xs)), math.nan)
        column, line = {x: i for i, x in enumerate(xs)}, {y: j for j, y in enumerate(ys)}
        for (x, y), value in points.items():
            values[line[y], column[x]] = value
        return HeadingMap(heading, np.array(xs), np.array(ys), values, True)
    keys = list(points)
    return HeadingMap(
        heading,
        np.array([x for x, _ in keys]),
        np.array([y for _, y in keys]),
        np.array([points[key] for key in keys]),
        False,
    )


def heading_maps(
    data: Any,
    column: str,
    *,
    speed: float | None = None,
    headings: Iterable[float] | None = None,
    one_per_point: bool = False,
) -> list[HeadingMap]:
    """The values of ``column`` over the ball positions, one map per heading.

    Args:
        data: Sweep rows (dicts with the :data:`optraj.sweeps.COLUMNS` keys) or a DataFrame.
        column: The column to map, e.g. ``"max_speed"`` [m/s] or ``"motion_time"`` [s].
        speed: Keep only the rows of this speed [m/s]; all rows when None.
        headings: The headings to map [deg]; every heading of the rows when None (one map
            of all of them when they are more than :data:`MAX_PANELS`, as in a random set).
        one_per_point: Refuse several speeds at one ball position (a value that depends on
            the speed, such as the motion time); otherwise a position's value is the largest
            of its rows'.

    Raises:
        InvalidInputError: No rows, a needed column missing, a speed or heading not in the
            rows (the message lists theirs), or several speeds where one is needed.
    """
    rows = rows_of(data)
    if not any(column in row for row in rows):
        raise InvalidInputError(
            f"the rows have no column {column!r}; they have {', '.join(rows[0])}",
            name="column",
            value=column,
        )
    rows = _at_speed(rows, speed)
    maps = []
    for heading in _headings(rows, headings):
        mine = [
            row
            for row in rows
            if heading is None
            or abs((_number(row["heading"]) or 0.0) - heading) <= HEADING_TOLERANCE
        ]
        maps.append(_one_map(heading, _points(mine, column, one_per_point)))
    return maps
