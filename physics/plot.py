"""Pictures of where the balls went: paths seen from above and heading-error distributions.

>>> figure = physics.plot_ball_paths({"DiffIKQP": outcomes_qp, "PID": outcomes_pid})
>>> figure = physics.plot_heading_errors({"DiffIKQP": outcomes_qp, "PID": outcomes_pid})

Both take ``{label: [Outcome, ...]}``; pool outcomes are drawn in each shot's own table frame
(the near cushion at x = 0, the table's long axis along x), so shots at different ball
positions share one table outline.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.physics.outcome import HEADING_TOLERANCE, Outcome
from optraj.planners.plot_style import legend_below, line_styles, pyplot
from optraj.problems.scenes import BALL_FROM_NEAR_END, TABLE_SIZE
from optraj.validation import as_choice

__all__ = ["LEGEND_PLACEMENTS", "plot_ball_paths", "plot_heading_errors"]

FloatArray = NDArray[np.float64]

#: Where :func:`plot_heading_errors` puts its legend.
LEGEND_PLACEMENTS = ("outside", "inside", "none")
#: The magnified view ends where a ball comes this close to a cushion [m] (a ball's radius
#: and some room): after a rebound, the distance off the line means nothing.
CUSHION_MARGIN = 0.04


def _groups(outcomes: Mapping[str, Sequence[Outcome]]) -> dict[str, list[Outcome]]:
    """The mapping as ``{label: [Outcome, ...]}``, each outcome's numbers finite where hit."""
    if not isinstance(outcomes, Mapping) or not outcomes:
        got = type(outcomes).__name__ if not isinstance(outcomes, Mapping) else "an empty one"
        raise InvalidInputError(
            f"outcomes must be a non-empty {{label: [physics.Outcome, ...]}} mapping, got {got}",
            name="outcomes",
        )
    groups: dict[str, list[Outcome]] = {}
    for label, items in outcomes.items():
        if not isinstance(label, str):
            raise InvalidInputError(
                f"outcome labels must be strings, got {label!r} ({type(label).__name__})",
                name="outcomes",
            )
        if isinstance(items, (str, bytes)) or not isinstance(items, Sequence) or not items:
            raise InvalidInputError(
                f"outcomes[{label!r}] must be a non-empty sequence of physics.Outcome, got "
                f"{type(items).__name__}",
                name="outcomes",
            )
        for index, item in enumerate(items):
            if not isinstance(item, Outcome):
                raise InvalidInputError(
                    f"outcomes[{label!r}][{index}] must be a physics.Outcome, got "
                    f"{type(item).__name__}",
                    name="outcomes",
                )
            numbers = [item.start, item.direction, item.roll, item.path]
            if item.hit:
                numbers.append(np.array([item.heading_error]))
            if not all(np.isfinite(value).all() for value in numbers):
                raise InvalidInputError(
                    f"outcomes[{label!r}][{index}] holds a non-finite number (heading error "
                    f"{item.heading_error!r})",
                    name="outcomes",
                )
        groups[label] = list(items)
    return groups


def _table_frame(outcome: Outcome, points: FloatArray) -> FloatArray:
    """``points`` (k, 3) in the shot's table frame: x from the near cushion, y from the side."""
    x0 = outcome.start[0] - BALL_FROM_NEAR_END
    y0 = outcome.start[1] - TABLE_SIZE[1] / 2
    return np.column_stack([points[:, 0] - x0, points[:, 1] - y0])


def _along_across(outcome: Outcome, points: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Distance along the commanded line [m] and off it [m] (left positive)."""
    d = outcome.direction[:2] / max(float(np.linalg.norm(outcome.direction[:2])), 1e-300)
    rel = points[:, :2] - outcome.start[:2]
    return rel @ d, rel @ np.array([-d[1], d[0]])


def _before_cushion(flat: FloatArray) -> int:
    """How many leading points (table frame) lie more than :data:`CUSHION_MARGIN` inside."""
    length, width = TABLE_SIZE
    x, y = flat[:, 0], flat[:, 1]
    m = CUSHION_MARGIN
    inside = (x > m) & (x < length - m) & (y > m) & (y < width - m)
    return int(np.argmin(inside)) if not inside.all() else len(inside)


def plot_ball_paths(outcomes: Mapping[str, Sequence[Outcome]]) -> Any:
    """Pool balls seen from above, one column per label; returns the figure.

    Top row: the table (2.54 m x 1.27 m inside the cushions) with each ball's path from the
    strike to rest (solid) and its commanded line (dashed grey); a missed ball is a cross.
    Bottom row: how far each ball is off its commanded line [mm] against the distance
    along it [m] until it nears a cushion, the same data magnified across the line.

    Args:
        outcomes: ``{label: [Outcome, ...]}`` of pool shots.

    Raises:
        InvalidInputError: An empty mapping, a label that is not a string, a non-outcome, a
            non-finite number, or a paddle outcome.
        MissingDependencyError: matplotlib is not installed.
    """
    groups = _groups(outcomes)
    for label, items in groups.items():
        for index, item in enumerate(items):
            if item.kind != "pool":
                raise InvalidInputError(
                    f"outcomes[{label!r}][{index}] is a {item.kind!r} outcome; ball paths are "
                    "drawn on a pool table, for pool outcomes only",
                    name="outcomes",
                )
    plt = pyplot()
    styles = line_styles(groups)
    columns = len(groups)
    figure, axes = plt.subplots(
        2,
        columns,
        figsize=(4.2 * columns, 6.4),
        squeeze=False,
        height_ratios=[1.1, 1.0],
        sharey="row",
    )
    length, width = TABLE_SIZE
    for column, (label, items) in enumerate(groups.items()):
        top, side = axes[0, column], axes[1, column]
        top.add_patch(
            plt.Rectangle((0, 0), length, width, facecolor="#1c7a45", edgecolor="#5a2d0c", lw=3)
        )
        missed = 0
        for o in items:
            start = _table_frame(o, o.start[None, :])[0]
            reach = length + width
            end = start + reach * o.direction[:2] / np.linalg.norm(o.direction[:2])
            top.plot(*np.stack([start, end]).T, color="0.85", lw=0.6, ls="--", zorder=2)
            if not o.hit:
                missed += 1
                top.plot(*start, marker="x", color="red", ms=7, zorder=4)
                continue
            points = np.concatenate([o.start[None, :], o.path, o.roll])
            flat = _table_frame(o, points)
            top.plot(flat[:, 0], flat[:, 1], color="white", lw=0.8, alpha=0.8, zorder=3)
            free = _before_cushion(flat)
            along, across = _along_across(o, points[:free])
            side.plot(along, across * 1e3, lw=0.8, alpha=0.7, color=styles[label].color)
        top.set_xlim(-0.1, length + 0.1)
        top.set_ylim(-0.1, width + 0.1)
        top.set_aspect("equal")
        title = f"{label}: {len(items)} shots" + (f", {missed} missed" if missed else "")
        top.set_title(title, fontsize=10)
        top.set_xlabel("x from the near cushion [m]")
        side.axhline(0.0, color="0.3", lw=0.8, ls="--")
        side.set_xlabel("along the commanded line [m]")
        side.grid(alpha=0.3)
        if column == 0:
            top.set_ylabel("y [m]")
            side.set_ylabel("off the line [mm] (left +)")
    figure.suptitle("Where the balls went, seen from above")
    figure.tight_layout()
    return figure


def plot_heading_errors(
    outcomes: Mapping[str, Sequence[Outcome]],
    *,
    ax: Any = None,
    title: str | None = None,
    legend: str = "outside",
) -> Any:
    """The distribution of |heading error| per label (share of shots at or below); the figure.

    Each label is a step curve on a log axis, in a style of its own (colour, dashes,
    markers, width: curves that lie on each other stay visible), with the 0.5 deg tolerance
    marked; a missed ball never reaches the curve's top, and the legend counts the misses.
    The legend is kept off the data: below a figure made here, or right of given axes.

    Args:
        outcomes: ``{label: [Outcome, ...]}``.
        ax: Axes to draw into; a new figure when None.
        title: The axes' title; a default when None.
        legend: ``"outside"`` (below a figure made here, right of given axes), ``"inside"``
            (the lower right corner, which the rising curves leave empty when most shots
            are within a degree) or ``"none"`` (for one legend of a whole grid of axes:
            ``figure.legend(*ax.get_legend_handles_labels())``).

    Raises:
        InvalidInputError: An empty mapping, a label that is not a string, a non-outcome, a
            non-finite number, or ``ax`` not Axes.
        UnknownNameError: An unknown ``legend`` placement.
        MissingDependencyError: matplotlib is not installed.
    """
    groups = _groups(outcomes)
    placement = as_choice(legend, "legend", LEGEND_PLACEMENTS)
    plt = pyplot()
    own = ax is None
    if ax is None:
        figure, ax = plt.subplots(figsize=(6.4, 4.6), layout="constrained")
    elif not hasattr(ax, "step") or not hasattr(ax, "figure"):
        raise InvalidInputError(
            f"ax must be matplotlib Axes or None, got {type(ax).__name__}", name="ax"
        )
    else:
        figure = ax.figure
    floor = 1e-4  # [deg] errors below this are drawn at it (a log axis has no zero)
    styles = line_styles(groups)
    for label, items in groups.items():
        errors = np.array([abs(o.heading_error) for o in items if o.hit])
        missed = len(items) - len(errors)
        share = np.arange(1, len(errors) + 1) / len(items)
        values = np.maximum(np.sort(errors), floor)
        name = f"{label} ({missed} missed)" if missed else label
        ax.step(np.concatenate([[floor], values]), np.concatenate([[0.0], share]), where="post",
                label=name, **styles[label].kwargs(len(values) + 1))  # fmt: skip
    ax.axvline(HEADING_TOLERANCE, color="0.3", ls="--", lw=0.8, label="tolerance")
    ax.set_xscale("log")
    ax.set_ylim(0.0, 1.02)
    ax.set_xlabel("|heading error| [deg]")
    ax.set_ylabel("share of shots at or below")
    ax.set_title(title if title is not None else "Heading error per controller", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    if placement == "outside" and own:
        legend_below(figure, *ax.get_legend_handles_labels())
    elif placement == "outside":
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    elif placement == "inside":
        ax.legend(fontsize=8, loc="lower right")
    return figure
