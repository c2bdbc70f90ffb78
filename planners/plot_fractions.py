"""Every joint at once, as a fraction of its limit: how close a plan runs to each limit.

One row of panels per quantity (position, velocity, acceleration, jerk, and torque when a
robot is given), one column per plan, every joint a curve of its own style, a dashed line at
1.0 (the limit). Jumps and unbounded values are drawn as in :mod:`.plot_jumps`.

>>> figure = plot_limit_fractions({"TOPPRA": toppra, "ruckig": fast}, robot.limits, robot=robot)
>>> limit_fractions(sample, robot.limits, "velocity")     # |qd| / velocity limit, (m, n)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.plot_jumps import (
    UNBOUNDED_LABEL,
    broken_curve,
    jump_times,
    legend_entries,
    mark_unbounded,
)
from optraj.planners.plot_panels import FIELD, QUANTITIES, check_dof, named, quantities_of
from optraj.planners.plot_style import legend_below, line_style, pyplot
from optraj.planners.trajectory import TrajectorySample
from optraj.robots import JointLimits, Robot

__all__ = ["FRACTION_QUANTITIES", "limit_fractions", "plot_limit_fractions"]

FloatArray = NDArray[np.float64]

#: The quantities a limit-fraction panel can show (torque needs the robot).
FRACTION_QUANTITIES = (*QUANTITIES, "torque")
#: The limit field of each quantity.
_LIMIT = {
    "velocity": "velocity",
    "acceleration": "acceleration",
    "jerk": "jerk",
    "torque": "effort",
}
#: The y-axis label of each quantity's row.
_AXIS = {
    "position": "position:\n|q - mid| / half range",
    "velocity": "|velocity| / limit",
    "acceleration": "|acceleration| / limit",
    "jerk": "|jerk| / limit",
    "torque": "|torque| / limit",
}


def limit_fractions(
    sample: TrajectorySample, limits: JointLimits, quantity: str, robot: Robot | None = None
) -> FloatArray:
    """Each joint's ``quantity`` as a fraction of its limit [-], shape (m, n).

    Position: the distance from the middle of the joint's range over half the range (1.0 at
    either bound, so asymmetric ranges read alike); velocity, acceleration, jerk: the
    magnitude over the limit; torque: the magnitude of the inverse-dynamics torque (gravity
    included) over the effort limit.

    Raises:
        UnknownNameError: An unknown quantity.
        InvalidInputError: Torque without a robot.
    """
    if quantity == "position":
        middle = (limits.upper + limits.lower) / 2
        return np.abs(sample.q - middle) / ((limits.upper - limits.lower) / 2)
    if quantity == "torque":
        if robot is None:
            raise InvalidInputError(
                "the torque fraction needs the robot (robot=...)", name="quantities"
            )
        torque = robot.inverse_dynamics(sample.q, sample.qd, sample.qdd)
        return np.abs(torque) / limits.effort
    quantities_of((quantity,), FRACTION_QUANTITIES)
    return np.abs(getattr(sample, FIELD[quantity])) / getattr(limits, _LIMIT[quantity])


def plot_limit_fractions(
    trajectories: Any,
    limits: JointLimits,
    *,
    robot: Robot | None = None,
    quantities: Sequence[str] | None = None,
    rate: float = 1000.0,
) -> Any:
    """Every joint's position, velocity, acceleration, jerk (and torque) over its limit.

    Args:
        trajectories: One plan, or several by label (one column of panels each).
        limits: The limits the fractions are of (``robot.limits``, or a problem's).
        robot: The robot, for the torque row (inverse dynamics); no torque row when None.
        quantities: The rows, from position, velocity, acceleration, jerk, torque; all four
            joint quantities (and torque with a robot) when None.
        rate: Sampling rate [Hz] (breakpoints are always included).

    Returns:
        The matplotlib figure: rows of quantities, columns of plans, a dashed line at 1.0,
        the joints' legend below.

    Raises:
        InvalidInputError: No trajectories, joint counts that differ from the limits' or the
            robot's, or torque without a robot.
        UnknownNameError: An unknown quantity.
        MissingDependencyError: matplotlib is not installed.
    """
    plans = named(trajectories)
    check_dof(plans, limits.n, "the limits")
    if robot is not None and robot.dof != limits.n:
        raise InvalidInputError(
            f"robot {robot.name!r} has {robot.dof} joints, the limits {limits.n}", name="robot"
        )
    default = FRACTION_QUANTITIES if robot is not None else QUANTITIES
    wanted = quantities_of(default if quantities is None else quantities, FRACTION_QUANTITIES)
    if "torque" in wanted and robot is None:
        raise InvalidInputError("the torque row needs the robot (robot=...)", name="quantities")
    plt = pyplot()
    rows, columns = len(wanted), len(plans)
    figure, axes = plt.subplots(
        rows,
        columns,
        sharex="col",
        sharey="row",
        squeeze=False,
        figsize=(1.6 + 4.2 * columns, 1.2 + 1.9 * rows),
        layout="constrained",
    )
    for column, (label, trajectory) in enumerate(plans.items()):
        sample = trajectory.sample(trajectory.times(rate))
        jumps, unbounded = jump_times(trajectory, limits)
        for row, quantity in enumerate(wanted):
            ax = axes[row, column]
            fractions = limit_fractions(sample, limits, quantity, robot)
            _joint_curves(ax, sample.t, fractions, limits, jumps.get(quantity, {}))
            noted = False
            for joint, times in sorted(unbounded.get(quantity, {}).items()):
                note = None if noted else UNBOUNDED_LABEL
                noted |= bool(
                    mark_unbounded(
                        ax, times, line_style(joint), limits.names[joint], note=note, beside=False
                    )
                )
            ax.axhline(
                1.0, color="k", linestyle="--", linewidth=1.0, gid="limit", label="limit (1.0)"
            )
            ax.grid(alpha=0.25)
            if column == 0:
                ax.set_ylabel(_AXIS[quantity])
        axes[0, column].set_title(label, fontsize="medium", pad=16)
        axes[-1, column].set_xlabel("time [s]")
    for row in range(rows):
        axes[row, 0].set_ylim(bottom=0.0, top=max(1.1, axes[row, 0].get_ylim()[1]))
    figure.suptitle("Every joint as a fraction of its limit (dashed: the limit)")
    legend_below(figure, *legend_entries(axes.flat))
    return figure


def _joint_curves(
    ax: Any,
    t: ArrayLike,
    fractions: FloatArray,
    limits: JointLimits,
    jumps: dict[int, list[float]],
) -> None:
    """One curve per joint, broken at that joint's jumps."""
    for joint in range(limits.n):
        x, y = broken_curve(t, fractions[:, joint], jumps.get(joint, []))
        ax.plot(x, y, label=limits.names[joint], **line_style(joint).kwargs(len(x)))
