"""Heat maps of a sweep over the table: the fastest reachable speed, the motion time.

One panel per heading, ball x and y [m] in the robot's base frame with the base (the
origin) marked; one colour bar with the unit. On a regular x/y grid each ball position is a
cell; a random set's shots are points. A cell or point without a value (the shot was
refused or failed) is hatched grey, or a grey cross. Matplotlib (the ``examples`` extra)
is imported when a function here is called, and the figures are made without pyplot, so
they draw headless; save one with ``figure.savefig("map.png")``.

>>> from optraj import sweeps
>>> figure = sweeps.plot_max_speed(sweeps.read_table("map.parquet"))          # doctest: +SKIP
>>> figure = sweeps.plot_motion_time(rows, speed=0.5)                          # doctest: +SKIP
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from optraj.errors import MissingDependencyError
from optraj.sweeps.columns import COLUMNS
from optraj.sweeps.maps import HeadingMap, heading_maps

__all__ = ["plot_max_speed", "plot_motion_time"]

#: Panels per row of a figure.
COLUMNS_PER_ROW = 4
#: Half the width of a cell [m] when the grid has one position along an axis.
LONE_CELL = 0.01
#: What a cell without a value is drawn as (matplotlib hatch).
NO_VALUE_HATCH = "///"


def _matplotlib() -> Any:
    """``matplotlib`` with its figure and colour modules, or a typed error naming the extra."""
    try:
        matplotlib = importlib.import_module("matplotlib")
        for name in ("figure", "colors", "cm", "patches", "lines"):
            importlib.import_module(f"matplotlib.{name}")
    except ImportError as exc:
        raise MissingDependencyError("matplotlib", "examples", "sweep heat maps") from exc
    return matplotlib


def plot_max_speed(rows: Any, *, headings: Iterable[float] | None = None) -> Any:
    """Heat map of the fastest cue speed the limits allow (``max_speed`` [m/s]); the figure.

    A ball position's value is the largest ``max_speed`` of its rows (all speeds); a
    position whose rows give none (out of reach, or refused without a speed) is hatched.

    Args:
        rows: Sweep rows (dicts with the :data:`optraj.sweeps.COLUMNS` keys) or a DataFrame.
        headings: The headings to draw [deg], one panel each; all of the rows' when None.

    Raises:
        InvalidInputError: No rows, a needed column missing, or a heading not in the rows.
        MissingDependencyError: matplotlib is not installed.
    """
    maps = heading_maps(rows, "max_speed", headings=headings)
    missing = "no max_speed: out of reach, or none recorded"
    return _draw(maps, "max_speed", "Fastest reachable cue speed", missing)


def plot_motion_time(
    rows: Any, *, speed: float | None = None, headings: Iterable[float] | None = None
) -> Any:
    """Heat map of the motion time [s] of the shots planned at ``speed``; the figure.

    Args:
        rows: Sweep rows (dicts with the :data:`optraj.sweeps.COLUMNS` keys) or a DataFrame.
        speed: Cue speed [m/s], one of the rows'; may be None when each ball position and
            heading has one row (one speed, or a random set).
        headings: The headings to draw [deg], one panel each; all of the rows' when None.

    Raises:
        InvalidInputError: No rows, a needed column missing, a speed or heading not in the
            rows, or no speed chosen among several.
        MissingDependencyError: matplotlib is not installed.
    """
    maps = heading_maps(rows, "motion_time", speed=speed, headings=headings, one_per_point=True)
    title = "Motion time" + ("" if speed is None else f" at {speed:.6g} m/s")
    return _draw(maps, "motion_time", title, "not planned: refused or failed")


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around ascending cell centres [m]: halfway between neighbours."""
    if len(centres) == 1:
        return np.array([centres[0] - LONE_CELL, centres[0] + LONE_CELL])
    middle = (centres[1:] + centres[:-1]) / 2
    return np.concatenate([[2 * centres[0] - middle[0]], middle, [2 * centres[-1] - middle[-1]]])


def _norm(maps: list[HeadingMap], mpl: Any) -> Any:
    """One colour scale over every panel's finite values (0 to 1 when there are none)."""
    finite = np.concatenate([m.values[np.isfinite(m.values)].ravel() for m in maps])
    if finite.size == 0:
        return mpl.colors.Normalize(0.0, 1.0)
    low, high = float(finite.min()), float(finite.max())
    if math.isclose(low, high):
        pad = 0.05 * max(abs(low), 1.0)  # one value: a scale around it
        low, high = low - pad, high + pad
    return mpl.colors.Normalize(low, high)


def _panel(ax: Any, one: HeadingMap, norm: Any, mpl: Any) -> None:
    """One heading's map on ``ax``: cells (or points), the no-value ones hatched grey."""
    missing = ~np.isfinite(one.values)
    if one.on_grid:
        xe, ye = _edges(one.x), _edges(one.y)
        if missing.any():
            ax.add_patch(
                mpl.patches.Rectangle(
                    (xe[0], ye[0]),
                    xe[-1] - xe[0],
                    ye[-1] - ye[0],
                    facecolor="0.85",
                    edgecolor="0.55",
                    hatch=NO_VALUE_HATCH,
                    linewidth=0.0,
                    zorder=0,
                )
            )
        values = np.ma.masked_invalid(one.values)
        ax.pcolormesh(xe, ye, values, cmap="viridis", norm=norm, zorder=1)
    else:
        keep = ~missing
        ax.scatter(one.x[keep], one.y[keep], c=one.values[keep], cmap="viridis", norm=norm, s=24)
        ax.scatter(one.x[missing], one.y[missing], marker="x", color="0.5", s=20)
    ax.plot(0.0, 0.0, marker="P", color="black", markersize=9, linestyle="none", zorder=3)
    ax.annotate("robot base", (0.0, 0.0), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlabel("ball x [m]")
    ax.set_ylabel("ball y [m]")
    ax.set_title("every heading" if one.heading is None else f"heading {one.heading:g} deg")
    ax.grid(alpha=0.3)


def _draw(maps: list[HeadingMap], column: str, title: str, missing: str) -> Any:
    """A figure of one panel per map with a shared colour bar.

    ``missing`` is the legend of the cells (or points) without a value.
    """
    mpl = _matplotlib()
    columns = min(len(maps), COLUMNS_PER_ROW)
    lines = math.ceil(len(maps) / columns)
    figure = mpl.figure.Figure(figsize=(3.6 * columns + 1.2, 3.6 * lines), layout="constrained")
    axes = figure.subplots(lines, columns, squeeze=False)
    norm = _norm(maps, mpl)
    for ax, one in zip(axes.flat, maps, strict=False):
        _panel(ax, one, norm, mpl)
    for ax in axes.flat[len(maps) :]:
        ax.set_visible(False)
    used = list(axes.flat[: len(maps)])
    unit = COLUMNS.get(column, ("", ""))[0]
    label = f"{column.replace('_', ' ')} [{unit}]" if unit else column.replace("_", " ")
    mappable = mpl.cm.ScalarMappable(norm=norm, cmap="viridis")
    figure.colorbar(mappable, ax=used, label=label)
    if any((~np.isfinite(one.values)).any() for one in maps):
        hatched = mpl.patches.Patch(
            facecolor="0.85", edgecolor="0.55", hatch=NO_VALUE_HATCH, label="no value"
        )
        cross = mpl.lines.Line2D([], [], marker="x", color="0.5", linestyle="none")
        grid = any(one.on_grid for one in maps)
        figure.legend(
            handles=[hatched if grid else cross],
            labels=[missing],
            loc="outside lower center",
        )
    figure.suptitle(title)
    return figure
