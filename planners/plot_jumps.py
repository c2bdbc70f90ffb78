"""Jumps in plots: curves broken where a quantity jumps, a marker where one is unbounded.

A trajectory may jump (LSPB's and TOPPRA's acceleration at their breakpoints, the pull-back
strike's velocity where the cue enters the line). Sampled, such a jump reads as a steep but
finite step, and the derivative above it as a finite value, though it is unbounded. The
jumps are taken from the independent checker (:func:`planners.checker.jumps.breakpoint_jumps`,
the same rule and round-off the checker's ``inf`` findings use), never detected again here.
A plot then breaks each curve at the jumps of its quantity and marks every instant where a
quantity is unbounded with a triangle on the top edge of its panel, a thin vertical line and
the label ``unbounded (jump)``.

>>> jumps = jump_times(trajectory, limits)      # {quantity: {joint: [t, ...]}}
>>> t, y = broken_curve(sample.t, values, jumps["acceleration"].get(joint, []))
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.planners.checker.joint_limits import ORDER
from optraj.planners.checker.jumps import breakpoint_jumps
from optraj.planners.checker.polynomials import derivatives_of
from optraj.planners.plot_style import LineStyle
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits

__all__ = [
    "UNBOUNDED_LABEL",
    "JumpTimes",
    "any_joint",
    "broken_curve",
    "jump_times",
    "legend_entries",
    "mark_unbounded",
]

FloatArray = NDArray[np.float64]

#: ``{quantity: {joint index: sorted jump times [s]}}``.
JumpTimes = dict[str, dict[int, list[float]]]

#: The text next to the markers, and the label their artists carry.
UNBOUNDED_LABEL = "unbounded (jump)"
#: Height of a row of markers above a panel, as a fraction of the panel's height.
ROW_HEIGHT = 0.075


def jump_times(trajectory: Trajectory, limits: JointLimits) -> tuple[JumpTimes, JumpTimes]:
    """Where each quantity jumps, and where it is unbounded, per joint.

    A quantity jumps where the checker finds a jump of its own order; it is unbounded where
    a lower order jumps (a velocity jump makes acceleration, jerk and torque unbounded).

    Args:
        trajectory: The trajectory.
        limits: Its joint limits (the scale of the checker's round-off).

    Returns:
        ``(jumps, unbounded)``, each ``{quantity: {joint: [t, ...]}}`` over position,
        velocity, acceleration, jerk and torque; a quantity or joint with none is absent.
    """
    knots = np.asarray(trajectory.breakpoints, dtype=float)
    derivatives = derivatives_of(np.asarray(trajectory.coefficients, dtype=float), 4)
    jumps: JumpTimes = {}
    unbounded: JumpTimes = {}
    for jump in breakpoint_jumps(derivatives, knots, limits):
        for quantity, order in ORDER.items():
            target = jumps if order == jump.order else unbounded if order > jump.order else None
            if target is not None:
                target.setdefault(quantity, {}).setdefault(jump.joint, []).append(jump.time)
    for found in (jumps, unbounded):
        for joints in found.values():
            for joint, times in joints.items():
                joints[joint] = sorted(set(times))
    return jumps, unbounded


def broken_curve(
    t: ArrayLike, values: ArrayLike, at: Iterable[float]
) -> tuple[FloatArray, FloatArray]:
    """The curve ``(t, values)`` with a gap (NaN) just before each time in ``at`` [s].

    The sample grid of :meth:`Trajectory.times` holds each breakpoint and the instant just
    before it, so the gap falls between the two sides of the jump: no line joins them.
    ``values`` may be (m,) or (m, k).
    """
    times = np.asarray(t, dtype=float)
    y = np.asarray(values, dtype=float)
    cuts = np.searchsorted(times, np.asarray(sorted(at), dtype=float))
    cuts = np.unique(cuts[(cuts > 0) & (cuts < len(times))])
    if cuts.size == 0:
        return times, y
    gap = np.full((len(cuts), *y.shape[1:]), np.nan)
    return np.insert(times, cuts, np.nan), np.insert(y, cuts, gap, axis=0)


def mark_unbounded(
    ax: Any,
    times: Iterable[float],
    style: LineStyle,
    who: str,
    *,
    row: int = 0,
    note: str | None = UNBOUNDED_LABEL,
    beside: bool = True,
) -> list[Any]:
    """Mark instants [s] where a quantity is unbounded on ``ax``; returns the artists.

    Each instant gets a triangle on the panel's top edge (above the data range, so it is
    never read as a value) and a thin vertical line across the panel, in the curve's colour.
    Several curves' markers go in rows (``row`` 0 on the edge, then upwards), each row
    labelled by ``note`` in the right margin (``beside``) or above the panel's right end
    (for panels side by side, whose margins are narrow).

    Args:
        ax: Matplotlib axes.
        times: The instants [s].
        style: The curve's style (its colour is used).
        who: The curve's label; the marker artist is labelled ``"<who>: unbounded (jump)"``.
        row: The row of markers, 0 on the top edge.
        note: The row's label; none when None.
        beside: Write the note in the right margin, else above the panel's right end.
    """
    instants = sorted(set(float(t) for t in times))
    if not instants:
        return []
    transform = ax.get_xaxis_transform()  # x in data, y in axes fractions
    height = 1.0 + ROW_HEIGHT * row
    artists = [
        ax.plot(
            instants,
            np.full(len(instants), height),
            linestyle="none",
            marker="^",
            markersize=8,
            color=style.color,
            markeredgecolor="black",
            markeredgewidth=0.6,
            transform=transform,
            clip_on=False,
            zorder=5,
            label=f"{who}: {UNBOUNDED_LABEL}",
        )[0]
    ]
    for instant in instants:
        artists.append(
            ax.axvline(
                instant,
                color=style.color,
                linewidth=0.7,
                linestyle=(0, (1, 2)),
                alpha=0.8,
                zorder=1,
                label=f"_{who} jump",
            )
        )
    if note is not None and beside:
        artists.append(
            ax.text(
                1.01,
                height,
                note,
                transform=ax.transAxes,
                ha="left",
                va="center",
                fontsize="x-small",
                color=style.color,
                fontweight="bold",
            )
        )
    elif note is not None:
        artists.append(
            ax.annotate(
                note,
                (1.0, height),
                xycoords="axes fraction",
                xytext=(0, 5),
                textcoords="offset points",
                ha="right",
                va="bottom",
                fontsize="x-small",
                color="0.2",
                fontweight="bold",
            )
        )
    return artists


def any_joint(found: Mapping[str, Mapping[int, list[float]]], quantity: str) -> list[float]:
    """Every instant [s] of ``found`` (jumps or unbounded) for ``quantity``, any joint."""
    return sorted({t for times in found.get(quantity, {}).values() for t in times})


def legend_entries(axes: Iterable[Any]) -> tuple[list[Any], list[str]]:
    """The legend entries of every panel, with one grey ``unbounded (jump)`` marker if any.

    The per-curve marker artists (coloured like their curves) stay out of the legend; a
    single neutral triangle stands for all of them.
    """
    handles: list[Any] = []
    labels: list[str] = []
    unbounded = False
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            if label.endswith(UNBOUNDED_LABEL):
                unbounded = True
            else:
                handles.append(handle)
                labels.append(label)
    if unbounded:
        from matplotlib.lines import Line2D

        handles.append(
            Line2D(
                [],
                [],
                linestyle="none",
                marker="^",
                markersize=8,
                color="0.6",
                markeredgecolor="black",
                markeredgewidth=0.6,
            )
        )
        labels.append(UNBOUNDED_LABEL)
    return handles, labels
