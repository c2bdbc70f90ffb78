"""Every joint of one trajectory: position, velocity, acceleration and jerk over time.

The picture behind ``Trajectory.plot()``: one panel per quantity, one curve per joint in a
style of its own, each joint's limits (when given) dashed in its colour, the phases named
along the top, and jumps and unbounded values drawn as in :mod:`.plot_jumps`.

>>> figure = plot_trajectory(traj, limits=robot.limits)
>>> figure = plot_trajectory(traj, quantities=("velocity",), ax=my_axes, linewidth=1.0)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.plot_jumps import (
    UNBOUNDED_LABEL,
    broken_curve,
    jump_times,
    legend_entries,
    mark_unbounded,
)
from optraj.planners.plot_panels import FIELD, QUANTITIES, quantities_of
from optraj.planners.plot_style import legend_below, line_style, pyplot
from optraj.planners.trajectory import Trajectory, TrajectorySample
from optraj.robots import JointLimits

__all__ = ["plot_trajectory", "scale_limits"]

#: Share of a panel's width one character of a phase name takes (x-small font, 8 in figure),
#: halved as the names are staggered on two rows.
CHARACTER_SHARE = 0.0045
_LIMIT = {"velocity": "velocity", "acceleration": "acceleration", "jerk": "jerk"}
#: Units of each quantity when no limits say whether a joint is revolute or prismatic.
_GENERIC_UNIT = {
    "position": "rad or m",
    "velocity": "rad/s or m/s",
    "acceleration": "rad/s^2 or m/s^2",
    "jerk": "rad/s^3 or m/s^3",
}


def plot_trajectory(
    trajectory: Trajectory,
    *,
    limits: JointLimits | None = None,
    quantities: Sequence[str] = QUANTITIES,
    ax: Any = None,
    rate: float = 1000.0,
    **kw: Any,
) -> Any:
    """All joints of one trajectory, one panel per quantity; returns the figure.

    Args:
        trajectory: The trajectory.
        limits: Limits to draw (each joint's dashed in its colour) and the units of the axes;
            none drawn when None (jumps are then judged on the trajectory's own scale).
        quantities: Panels, from position, velocity, acceleration, jerk.
        ax: Axes to draw into: one per quantity (a single Axes for one quantity); a new
            figure when None.
        rate: Sampling rate [Hz] (breakpoints are always included).
        **kw: Passed to every curve's ``Axes.plot`` (e.g. ``linewidth=1``), over the style.

    Raises:
        InvalidInputError: Not a Trajectory, limits for another joint count, or ``ax`` not
            one Axes per quantity.
        UnknownNameError: An unknown quantity.
        MissingDependencyError: matplotlib is not installed.
    """
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    if limits is not None and limits.n != trajectory.dof:
        raise InvalidInputError(
            f"the trajectory has {trajectory.dof} joints, the limits {limits.n}", name="limits"
        )
    wanted = quantities_of(quantities, QUANTITIES)
    sample = trajectory.sample(trajectory.times(rate))
    figure, axes = _axes(ax, len(wanted))
    jumps, unbounded = jump_times(trajectory, limits or scale_limits(trajectory, sample))
    for panel, quantity in zip(axes, wanted, strict=True):
        values = getattr(sample, FIELD[quantity])
        noted = False
        for joint in range(trajectory.dof):
            style = line_style(joint)
            t, y = broken_curve(sample.t, values[:, joint], jumps.get(quantity, {}).get(joint, []))
            panel.plot(t, y, label=trajectory.joint_names[joint], **{**style.kwargs(len(t)), **kw})
            if limits is not None:
                _limits(panel, quantity, limits, joint, style.color)
            instants = unbounded.get(quantity, {}).get(joint, [])
            note = None if noted else UNBOUNDED_LABEL
            noted |= bool(
                mark_unbounded(
                    panel, instants, style, trajectory.joint_names[joint], note=note, beside=False
                )
            )
        unit = _GENERIC_UNIT[quantity] if limits is None else limits.unit(quantity, 0)
        if limits is not None and len(set(limits.kinds)) > 1:
            unit = _GENERIC_UNIT[quantity]
        panel.set_ylabel(f"{quantity} [{unit}]")
        panel.grid(alpha=0.25)
    _phases(axes[0], trajectory)
    axes[-1].set_xlabel("time [s]")
    planner = trajectory.metadata.get("planner", "trajectory")
    axes[0].set_title(
        f"{planner}: every joint over {trajectory.duration:.3g} s"
        + ("; dashed: each joint's limits" if limits is not None else ""),
        fontsize="medium",
        pad=22,
    )
    if ax is None:
        legend_below(figure, *legend_entries(axes))
    return figure


def _axes(ax: Any, count: int) -> tuple[Any, list[Any]]:
    """The figure and one axes per panel: new ones, or those given, checked."""
    if ax is None:
        plt = pyplot()
        figure, axes = plt.subplots(
            count,
            1,
            sharex=True,
            figsize=(8.0, 1.3 + 2.1 * count),
            layout="constrained",
            squeeze=False,
        )
        return figure, list(axes[:, 0])
    given = [ax] if hasattr(ax, "plot") else list(ax) if isinstance(ax, Sequence) else []
    if len(given) != count or not all(hasattr(a, "plot") and hasattr(a, "figure") for a in given):
        raise InvalidInputError(
            f"ax must be matplotlib Axes, one per quantity ({count}), got {ax!r}", name="ax"
        )
    return given[0].figure, given


def _limits(ax: Any, quantity: str, limits: JointLimits, joint: int, color: str) -> None:
    """One joint's bounds of ``quantity``, thin and dashed in its colour."""
    if quantity == "position":
        bounds = (limits.lower[joint], limits.upper[joint])
    else:
        value = float(getattr(limits, _LIMIT[quantity])[joint])
        bounds = (-value, value)
    for bound in bounds:
        ax.axhline(
            bound,
            color=color,
            linestyle="--",
            linewidth=0.8,
            alpha=0.7,
            gid="limit",
            label="_limit",
        )


def _phases(ax: Any, trajectory: Trajectory) -> None:
    """Phase boundaries as thin grey lines, the name of each phase wide enough above it.

    Names go on two staggered rows; one that would not fit over its phase is left out
    (a pick-and-place has 14 phases, some a fraction of a second long).
    """
    transform = ax.get_xaxis_transform()
    for k, phase in enumerate(trajectory.phases):
        ax.axvline(phase.t_start, color="0.5", linewidth=0.6, zorder=0)
        share = (phase.t_end - phase.t_start) / trajectory.duration
        if share < CHARACTER_SHARE * len(phase.name):
            continue
        middle = (phase.t_start + phase.t_end) / 2
        ax.text(
            middle,
            1.01 + 0.07 * (k % 2),
            phase.name,
            transform=transform,
            ha="center",
            va="bottom",
            fontsize="x-small",
            color="0.3",
        )


def scale_limits(trajectory: Trajectory, sample: TrajectorySample) -> JointLimits:
    """Limits on the trajectory's own scale, for judging its jumps when none are given.

    The checker's jump rule allows a round-off relative to each quantity's limit; here the
    limit is the trajectory's own peak of that quantity (plus one unit, so never zero).
    """
    n = trajectory.dof
    peak = {
        name: np.max(np.abs(getattr(sample, field)), axis=0) + 1.0 for name, field in FIELD.items()
    }
    return JointLimits(
        names=tuple(trajectory.joint_names),
        kinds=("rad",) * n,
        lower=np.min(sample.q, axis=0) - 1.0,
        upper=np.max(sample.q, axis=0) + 1.0,
        velocity=peak["velocity"],
        acceleration=peak["acceleration"],
        jerk=peak["jerk"],
        effort=np.ones(n),
    )
