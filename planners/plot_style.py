"""The look shared by every plot: matplotlib on demand, one line style per curve, legends.

Curves of different planners often lie on top of each other (LSPB exactly under TOPPRA, the
quintic under optimal control). Each label therefore gets a colour, a dash pattern, sparse
markers at an offset of their own, and a line width that shrinks with its index, so that a
curve drawn first stays visible around the ones drawn over it.

>>> styles = line_styles(["cubic", "LSPB", "TOPPRA"])
>>> ax.plot(t, y, label="LSPB", **styles["LSPB"].kwargs())        # doctest: +SKIP
>>> legend_below(figure, *ax.get_legend_handles_labels())          # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from optraj.errors import InvalidInputError, MissingDependencyError

__all__ = [
    "BAR_HEIGHT",
    "COLOURS",
    "DASHES",
    "MARKERS",
    "LineStyle",
    "legend_below",
    "line_style",
    "line_styles",
    "pyplot",
    "shade_phase",
]

#: Colours of the style cycle (matplotlib's colour-blind friendly "tab10" order).
COLOURS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)
#: Dash patterns of the style cycle (matplotlib ``linestyle``; the first is solid).
DASHES: tuple[str | tuple[int, tuple[int, ...]], ...] = (
    "-",
    (0, (6, 2)),
    (0, (3, 1, 1, 1)),
    (0, (1, 1)),
    (0, (8, 2, 2, 2, 2, 2)),
    (0, (4, 3)),
)
#: Markers of the style cycle, drawn sparsely along each curve.
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")
#: Line width of the first curve and how much each later one is thinner [pt].
WIDEST = 3.2
NARROWING = 0.45
THINNEST = 1.0
#: Distance between two markers of one curve, and the shift of each curve's first marker,
#: as fractions of the axes' diagonal (matplotlib ``markevery`` with floats).
MARKER_SPACING = 0.12
MARKER_SHIFT = 0.023
#: Height of a phase bar (:func:`shade_phase`), as a fraction of the panel's height.
BAR_HEIGHT = 0.035
#: Characters of a legend label (small font) per inch of figure width, and the width of a
#: legend entry's handle and gaps, in characters.
LEGEND_CHARACTERS_PER_INCH = 12.0
LEGEND_HANDLE_CHARACTERS = 7
#: Markers on a curve whose number of points is known (:meth:`LineStyle.kwargs`).
MARKERS_PER_CURVE = 9


def pyplot() -> Any:
    """``matplotlib.pyplot``, or a typed error naming the extra that installs it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("matplotlib", "examples", "plotting") from exc
    return plt


@dataclass(frozen=True)
class LineStyle:
    """How one curve is drawn.

    Attributes:
        color: Matplotlib colour.
        linestyle: Matplotlib dash pattern.
        marker: Matplotlib marker, drawn every :data:`MARKER_SPACING` of the axes' diagonal.
        linewidth: Line width [pt].
        markevery: Matplotlib ``markevery`` (first marker, spacing) as axes fractions.
    """

    color: str
    linestyle: str | tuple[int, tuple[int, ...]]
    marker: str
    linewidth: float
    markevery: tuple[float, float]

    def kwargs(self, points: int | None = None) -> dict[str, Any]:
        """Keyword arguments of ``Axes.plot`` that draw a curve in this style.

        Args:
            points: The curve's number of points: its markers are then spaced evenly in
                sample index (time, on a uniform grid), :data:`MARKERS_PER_CURVE` of them;
                when None, evenly along the drawn line (many where the line zig-zags).
        """
        markevery: Any = self.markevery
        if points is not None and points > 0:
            step = max(points // MARKERS_PER_CURVE, 1)
            shift = int(self.markevery[0] / MARKER_SPACING * step)
            markevery = slice(shift, None, step)
        return {
            "color": self.color,
            "linestyle": self.linestyle,
            "linewidth": self.linewidth,
            "marker": self.marker,
            "markevery": markevery,
            "markersize": 4.5,
            "markerfacecolor": "white",
            "markeredgecolor": self.color,
            "markeredgewidth": 1.2,
        }


def line_style(index: int) -> LineStyle:
    """The style of the ``index``-th curve (0-based) of the cycle.

    Colours repeat after 10 curves, dashes after 6 and markers after 8, so no two of the
    first 120 curves share all three.

    Raises:
        InvalidInputError: A negative or non-integer index.
    """
    if isinstance(index, bool) or not isinstance(index, int) or index < 0:
        raise InvalidInputError(f"index must be an integer >= 0, got {index!r}", name="index")
    return LineStyle(
        color=COLOURS[index % len(COLOURS)],
        linestyle=DASHES[index % len(DASHES)],
        marker=MARKERS[index % len(MARKERS)],
        linewidth=max(WIDEST - NARROWING * index, THINNEST),
        markevery=((MARKER_SHIFT * index) % MARKER_SPACING, MARKER_SPACING),
    )


def line_styles(labels: Iterable[str]) -> dict[str, LineStyle]:
    """One style per label, in order (the first label gets the widest line)."""
    return {label: line_style(index) for index, label in enumerate(labels)}


def legend_below(figure: Any, handles: Sequence[Any], labels: Sequence[str]) -> Any:
    """A figure legend under the axes, off the data; returns it (None when no handles).

    Labels repeated (one handle per panel) are kept once. The figure must use the
    constrained layout, which makes room for the legend below.
    """
    seen: dict[str, Any] = {}
    for handle, label in zip(handles, labels, strict=True):
        if not label.startswith("_"):
            seen.setdefault(label, handle)
    if not seen:
        return None
    # as many columns as the longest label lets fit across the figure, at most 4
    widest = max(len(label) for label in seen) + LEGEND_HANDLE_CHARACTERS
    fit = int(figure.get_figwidth() * LEGEND_CHARACTERS_PER_INCH / widest)
    columns = max(1, min(len(seen), 4, fit))
    return figure.legend(
        list(seen.values()),
        list(seen.keys()),
        loc="outside lower center",
        ncols=columns,
        fontsize="small",
        frameon=False,
    )


def shade_phase(ax: Any, start: float, end: float, style: LineStyle, row: int) -> None:
    """Shade a phase window [s] in a curve's colour, with a bar of its own along the bottom.

    The pale band spans the panel; the bar (row ``row`` from the bottom, one per curve) says
    whose band it is where the bands of several curves overlap.
    """
    ax.axvspan(start, end, color=style.color, alpha=0.07, zorder=0, linewidth=0)
    height = 0.035
    ax.axvspan(
        start,
        end,
        ymin=height * row,
        ymax=height * (row + 1),
        color=style.color,
        alpha=0.6,
        zorder=0,
        linewidth=0,
    )
