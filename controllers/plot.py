"""Pictures of closed-loop runs: tool error over time, joint speeds against their limits.

Matplotlib is imported when a function here is called, not when :mod:`controllers` is
imported, so the controllers work headless and import fast (``pip install optraj[examples]``
brings matplotlib).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from optraj.controllers.simulation import Result
from optraj.errors import InvalidInputError
from optraj.planners.plot_style import legend_below, line_styles, pyplot
from optraj.robots import JointLimits

__all__ = ["plot_tracking"]


def plot_tracking(
    results: Result | Sequence[Result], limits: JointLimits, *, joint: int | None = None
) -> Any:
    """Compare runs: tool position error, tool speed error and commanded joint speed.

    Each run has a style of its own (colour, dashes, markers, width) so that runs that
    track alike stay visible; the plan's strike window is shaded; the legend is below.

    Args:
        results: One run or several (e.g. one per controller) on the same plan.
        limits: The limits to draw (``robot.limits``).
        joint: The joint whose commanded speed is drawn; the one that comes nearest to (or
            goes furthest beyond) its limit in any run when None.

    Returns:
        The matplotlib figure (three panels sharing the time axis).

    Raises:
        InvalidInputError: No results, or a joint index out of range.
        MissingDependencyError: matplotlib is not installed.
    """
    runs = [results] if isinstance(results, Result) else list(results)
    if not runs or not all(isinstance(r, Result) for r in runs):
        raise InvalidInputError("results must be one or more controllers.Result", name="results")
    n = limits.n
    if joint is None:
        ratios = [np.max(np.abs(r.command) / limits.velocity, axis=0) for r in runs]
        joint = int(np.argmax(np.max(ratios, axis=0)))
    elif isinstance(joint, bool) or not isinstance(joint, (int, np.integer)) or not 0 <= joint < n:
        raise InvalidInputError(f"joint must be in [0, {n - 1}], got {joint}", name="joint")
    styles = line_styles(_labels(runs))
    plt = pyplot()
    figure, (error_axes, speed_axes, joint_axes) = plt.subplots(
        3, 1, sharex=True, figsize=(8.0, 8.6), layout="constrained"
    )
    for run, (label, style) in zip(runs, styles.items(), strict=True):
        m = run.metrics
        look = style.kwargs(len(run.t))
        p = run.references.T_world_tool[:, :3, 3]
        realised = run.T_world_tool[:, :3, 3]
        name = f"{label} (max {1e3 * m.position_max:.2f} mm)"
        error_axes.plot(run.t, 1e3 * np.linalg.norm(realised - p, axis=1), label=name, **look)
        planned = np.linalg.norm(run.references.twist[:, :3], axis=1)
        actual = np.linalg.norm(np.gradient(realised, run.t, axis=0), axis=1)
        speed_axes.plot(run.t, 1e3 * (actual - planned), label=name, **look)
        joint_axes.step(
            run.t[:-1],
            run.command[:, joint],
            where="post",
            label=name,
            **style.kwargs(len(run.t) - 1),
        )
    limit = limits.velocity[joint]
    for sign in (1.0, -1.0):
        joint_axes.axhline(
            sign * limit,
            color="k",
            linestyle="--",
            linewidth=0.9,
            gid="limit",
            label="speed limit" if sign > 0 else "_speed limit",
        )
    strike = runs[0].metrics.strike
    if strike is not None:
        for axes in (error_axes, speed_axes, joint_axes):
            axes.axvspan(
                *strike.window,
                color="0.88",
                zorder=0,
                linewidth=0,
                label="strike window of the plan",
            )
    error_axes.set_ylabel("tool position error [mm]")
    error_axes.set_title(
        "Tracking one plan: each controller's tool error and commanded joint speed",
        fontsize="medium",
    )
    speed_axes.set_ylabel("tool speed - planned [mm/s]")
    joint_axes.set_ylabel(f"command {limits.names[joint]} [{limits.unit('velocity', joint)}]")
    joint_axes.set_xlabel("time [s]")
    for axes in (error_axes, speed_axes, joint_axes):
        axes.grid(alpha=0.25)
    handles, labels = [], []
    for axes in (error_axes, joint_axes):
        more_handles, more_labels = axes.get_legend_handles_labels()
        handles += more_handles
        labels += more_labels
    legend_below(figure, handles, labels)
    return figure


def _labels(runs: Sequence[Result]) -> list[str]:
    """One label per run: its controller's name, numbered when two runs share one."""
    names = [run.controller for run in runs]
    return [
        f"{name} ({names[:k].count(name) + 1})" if names.count(name) > 1 else name
        for k, name in enumerate(names)
    ]
