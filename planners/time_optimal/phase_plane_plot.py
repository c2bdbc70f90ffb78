"""A picture of TOPPRA's phase plane: the planned path velocity under the limits' bounds.

Matplotlib is imported when :func:`plot_phase_plane` is called (through
:func:`planners.plot.pyplot <optraj.planners.plot.pyplot>`), not with the planners.

Example::

    plane = phase_plane(problem, traj)
    figure = plot_phase_plane(plane)
    figure.savefig("phase_plane.png")
"""

from __future__ import annotations

from typing import Any

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.plot import pyplot
from optraj.planners.time_optimal.phase_plane import PhasePlane

__all__ = ["plot_phase_plane"]

#: The y axis ends this far above the highest bound drawn, so no line runs along the frame.
_HEADROOM = 1.1
#: A bound is drawn up to this multiple of the plan's peak path velocity; higher parts leave
#: the axes (they would flatten the plan) [-].
_REACH = 2.5


def plot_phase_plane(plane: PhasePlane, *, ax: Any = None) -> Any:
    """The plan's path velocity over the path position, under each limit's bound.

    Drawn: each limit's own bound (thin, dashed; a limit that bounds nothing is named in the
    legend as unbounded), the maximum velocity curve of every limit together (grey band),
    the controllable bound (dash-dotted) and the plan (thick). The legend sits beside the
    axes, off the data.

    Args:
        plane: The phase plane, from :func:`~planners.time_optimal.phase_plane.phase_plane`.
        ax: Matplotlib axes to draw on; a new figure when None.

    Returns:
        The matplotlib figure.

    Raises:
        InvalidInputError: ``plane`` is not a PhasePlane.
        MissingDependencyError: matplotlib is not installed.
    """
    if not isinstance(plane, PhasePlane):
        raise InvalidInputError(
            f"plane must be a PhasePlane (from phase_plane), got {type(plane).__name__}",
            name="plane",
        )
    plt = pyplot()
    drawn_here = ax is None
    if ax is None:
        figure, ax = plt.subplots(figsize=(8.5, 3.4), layout="constrained")
    else:
        figure = ax.figure
    unit = plane.unit
    ax.fill_between(
        plane.s,
        0.0,
        _finite(plane.sd_max),
        color="0.85",
        linewidth=0.0,
        label="feasible: under the maximum velocity curve",
    )
    ax.plot(plane.s, _finite(plane.sd_max), color="0.45", linewidth=1.2)
    top = float(np.max(plane.sd))
    drawn = np.concatenate([_finite(plane.sd_max), plane.sd_controllable, plane.sd])
    highest = float(np.nanmax(np.where(drawn <= _REACH * top, drawn, np.nan)))
    ceiling = _HEADROOM * max(highest, top, 1e-12)
    styles = ("--", ":", (0, (8, 3)), (0, (1, 3)))
    for k, (name, bound) in enumerate(plane.bounds.items()):
        finite = bound[np.isfinite(bound)]
        note = (
            ": no bound on this path"
            if finite.size == 0
            else " (above the axes)"
            if float(np.min(finite)) > ceiling
            else ""
        )
        ax.plot(
            plane.s,
            _finite(bound),
            linestyle=styles[k % len(styles)],
            linewidth=1.3,
            color=f"C{k + 1}",
            label=f"{name} limit alone{note}",
        )
    ax.plot(
        plane.s,
        plane.sd_controllable,
        linestyle="-.",
        color="C5",
        linewidth=1.3,
        label="controllable: the end still reachable",
    )
    ax.plot(plane.s, plane.sd, color="C0", linewidth=2.2, label="TOPPRA's plan")
    ax.set_ylim(0.0, ceiling)
    ax.set_xlim(float(plane.s[0]), float(plane.s[-1]))
    ax.set_xlabel(f"path position s [{unit}]")
    ax.set_ylabel(f"path velocity ds/dt [{unit}/s]")
    ax.set_title("TOPPRA's phase plane")
    if drawn_here:  # beside the axes, in the figure's layout
        figure.legend(loc="outside right upper", fontsize="small", frameon=False)
    else:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    return figure


def _finite(values: Any) -> Any:
    """The values with inf as NaN, which matplotlib leaves out of a line."""
    return np.where(np.isfinite(values), values, np.nan)
