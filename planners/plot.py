"""Pictures of plans: joint profiles against their limits, tool speed, the arm in 3-D.

Matplotlib is imported when a function here is called, not when :mod:`planners` is imported,
so the planners work headless and import fast (``pip install optraj[examples]`` brings
matplotlib). Every function returns the figure; save it with ``figure.savefig(path)``.

What every plot here shares (:mod:`.plot_style`, :mod:`.plot_jumps`): each plan (or joint)
has a colour, dash pattern, sparse markers and line width of its own, so that curves lying
on top of each other stay visible; legends sit below the panels, off the data; a strike
phase is shaded in its plan's colour; and where the checker finds a jump, the curve is
broken there and every quantity the jump makes unbounded is marked ``unbounded (jump)`` by
a triangle on the panel's top edge, never drawn as a finite value.

>>> figure = plot_profiles({"cubic": cubic, "ruckig": fast}, robot.limits)
>>> figure = plot_trajectory(fast, limits=robot.limits)        # every joint of one plan
>>> figure = plot_limit_fractions({"ruckig": fast}, robot.limits, robot=robot)
>>> figure.savefig("profiles.png")
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.plot_arm import MAX_FIGURES, joint_origins, plot_robot
from optraj.planners.plot_fractions import plot_limit_fractions
from optraj.planners.plot_jumps import (
    UNBOUNDED_LABEL,
    any_joint,
    broken_curve,
    jump_times,
    legend_entries,
    mark_unbounded,
)
from optraj.planners.plot_panels import (
    FIELD,
    QUANTITIES,
    check_dof,
    named,
    quantities_of,
    samples_of,
    shade_strikes,
)
from optraj.planners.plot_style import legend_below, line_styles, pyplot
from optraj.planners.plot_trajectory import plot_trajectory
from optraj.planners.trajectory import TrajectorySample
from optraj.robots import JointLimits, Robot

__all__ = [
    "MAX_FIGURES",
    "joint_origins",
    "plot_limit_fractions",
    "plot_profiles",
    "plot_robot",
    "plot_tool_speed",
    "plot_trajectory",
    "pyplot",
]

_LIMIT = {"velocity": "velocity", "acceleration": "acceleration", "jerk": "jerk"}


def plot_profiles(
    trajectories: Any,
    limits: JointLimits,
    *,
    joint: int | None = None,
    quantities: Sequence[str] = QUANTITIES,
    rate: float = 1000.0,
) -> Any:
    """Position, velocity, acceleration and jerk of one joint, each against its limits.

    Each plan is drawn in a style of its own (colour, dashes, markers, width). A quantity
    that jumps is drawn with a gap at the jump; one that a lower jump makes unbounded (the
    jerk of LSPB and TOPPRA, the acceleration of the pull-back strike) gets a triangle on
    the panel's top edge labelled ``unbounded (jump)`` at each such instant. A plan's
    ``strike`` phase is shaded in its colour.

    Args:
        trajectories: One plan (a :class:`Trajectory`), or several by label (e.g. one per
            planner) on one time axis.
        limits: The limits to draw (dashed): position bounds, +-velocity, ...
        joint: Joint index; the one that comes nearest to (or beyond) its velocity limit in
            any plan when None.
        quantities: Panels, a subset of position, velocity, acceleration, jerk.
        rate: Sampling rate [Hz] (breakpoints are always included).

    Returns:
        The matplotlib figure, one panel per quantity, the legend below them.

    Raises:
        InvalidInputError: No trajectories, joint counts that differ from the limits', or a
            joint index out of range.
        UnknownNameError: An unknown quantity.
        MissingDependencyError: matplotlib is not installed.
    """
    plans = named(trajectories)
    check_dof(plans, limits.n, "the limits")
    wanted = quantities_of(quantities, QUANTITIES)
    samples = samples_of(plans, rate)
    joint = _joint(joint, samples, limits)
    styles = line_styles(plans)
    found = {label: jump_times(t, limits) for label, t in plans.items()}
    plt = pyplot()
    figure, axes = plt.subplots(
        len(wanted), 1, sharex=True, figsize=(8.0, 1.2 + 2.1 * len(wanted)), layout="constrained"
    )
    axes = np.atleast_1d(axes)
    for ax, quantity in zip(axes, wanted, strict=True):
        row = 0
        for label, sample in samples.items():
            jumps, unbounded = found[label]
            values = getattr(sample, FIELD[quantity])[:, joint]
            t, y = broken_curve(sample.t, values, jumps.get(quantity, {}).get(joint, []))
            ax.plot(t, y, label=label, **styles[label].kwargs(len(t)))
            instants = unbounded.get(quantity, {}).get(joint, [])
            note = f"{label}: {UNBOUNDED_LABEL}"
            row += bool(mark_unbounded(ax, instants, styles[label], label, row=row, note=note))
        _limit_lines(ax, quantity, limits, joint)
        shade_strikes(ax, plans, styles)
        ax.set_ylabel(f"{quantity} [{limits.unit(quantity, joint)}]")
        ax.grid(alpha=0.25)
    axes[0].set_title(
        f"joint {limits.names[joint]!r}; dashed black: its limits; "
        "triangles on top: unbounded (a lower derivative jumps)",
        fontsize="medium",
    )
    axes[-1].set_xlabel("time [s]")
    legend_below(figure, *legend_entries(axes))
    return figure


def _joint(joint: int | None, samples: Mapping[str, TrajectorySample], limits: JointLimits) -> int:
    """The joint index asked for, checked; when None, the one nearest its velocity limit."""
    if joint is None:
        ratios = [np.max(np.abs(s.qd), axis=0) / limits.velocity for s in samples.values()]
        return int(np.argmax(np.max(ratios, axis=0)))
    if isinstance(joint, bool) or not isinstance(joint, (int, np.integer)):
        raise InvalidInputError(f"joint must be an integer index, got {joint!r}", name="joint")
    if not 0 <= joint < limits.n:
        raise InvalidInputError(f"joint must be in [0, {limits.n - 1}], got {joint}", name="joint")
    return int(joint)


def _limit_lines(ax: Any, quantity: str, limits: JointLimits, joint: int) -> None:
    """The joint's two bounds of ``quantity``, dashed black, labelled ``limit``."""
    if quantity == "position":
        bounds = (limits.lower[joint], limits.upper[joint])
    else:
        value = getattr(limits, _LIMIT[quantity])[joint]
        bounds = (-value, value)
    for k, bound in enumerate(bounds):
        ax.axhline(
            bound,
            color="k",
            linestyle="--",
            linewidth=0.9,
            gid="limit",
            label="limit" if k == 0 else "_limit",
        )


def plot_tool_speed(
    robot: Robot,
    trajectories: Any,
    *,
    rate: float = 500.0,
) -> Any:
    """Speed of the tool frame origin over time, each plan's strike phase in its colour.

    Where a plan's joint velocity jumps (the pull-back strike entering its line), its speed
    curve is broken instead of joined by a vertical line.

    Args:
        robot: The robot the plans are for.
        trajectories: One plan, or several by label.
        rate: Sampling rate [Hz].

    Returns:
        The matplotlib figure.

    Raises:
        InvalidInputError: No trajectories, or one for another joint count.
        MissingDependencyError: matplotlib is not installed.
    """
    plans = named(trajectories)
    check_dof(plans, robot.dof, f"robot {robot.name!r}")
    styles = line_styles(plans)
    plt = pyplot()
    figure, ax = plt.subplots(figsize=(8.0, 4.4), layout="constrained")
    for label, trajectory in plans.items():
        sample = samples_of({label: trajectory}, rate)[label]
        speed = np.linalg.norm(
            np.einsum("mij,mj->mi", robot.jacobian(sample.q)[:, :3], sample.qd), axis=1
        )
        jumps, _ = jump_times(trajectory, robot.limits)
        t, y = broken_curve(sample.t, speed, any_joint(jumps, "velocity"))
        ax.plot(t, y, label=label, **styles[label].kwargs(len(t)))
    shade_strikes(ax, plans, styles)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"tool speed [m/s] (frame {robot.tool_frame})")
    ax.set_title(
        "Tool speed; bands and bars at the bottom: each plan's strike phase", fontsize="medium"
    )
    ax.grid(alpha=0.25)
    handles, labels = ax.get_legend_handles_labels()
    legend_below(figure, handles, labels)
    return figure
