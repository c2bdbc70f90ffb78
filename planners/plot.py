"""Pictures of plans: joint profiles against their limits, tool speed, the arm in 3-D.

Matplotlib is imported when a function here is called, not when :mod:`planners` is imported,
so the planners work headless and import fast (``pip install optraj[examples]`` brings
matplotlib). Every function returns the figure; save it with ``figure.savefig(path)``.

>>> figure = plot_profiles({"cubic": cubic, "ruckig": fast}, robot.limits)
>>> figure.savefig("profiles.png")
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.planners.trajectory import Trajectory, TrajectorySample
from optraj.robots import JointLimits, Robot
from optraj.validation import as_choice, as_count

__all__ = ["joint_origins", "plot_profiles", "plot_robot", "plot_tool_speed", "pyplot"]

FloatArray = NDArray[np.float64]

_QUANTITIES = ("position", "velocity", "acceleration", "jerk")
_FIELD = {"position": "q", "velocity": "qd", "acceleration": "qdd", "jerk": "jerk"}
_LIMIT = {"velocity": "velocity", "acceleration": "acceleration", "jerk": "jerk"}


def pyplot() -> Any:
    """``matplotlib.pyplot``, or a typed error naming the extra that installs it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("matplotlib", "examples", "plotting") from exc
    return plt


def _named(trajectories: Trajectory | Mapping[str, Trajectory]) -> dict[str, Trajectory]:
    if isinstance(trajectories, Trajectory):
        label = str(trajectories.metadata.get("planner", "trajectory"))
        return {label: trajectories}
    if isinstance(trajectories, Mapping) and trajectories:
        named = dict(trajectories)
        if all(isinstance(t, Trajectory) for t in named.values()):
            return {str(k): v for k, v in named.items()}
    raise InvalidInputError(
        "trajectories must be a planners.Trajectory or a non-empty {label: Trajectory} mapping",
        name="trajectories",
    )


def _samples(trajectory: Trajectory, rate: float) -> TrajectorySample:
    return trajectory.sample(trajectory.times(rate))


def plot_profiles(
    trajectories: Trajectory | Mapping[str, Trajectory],
    limits: JointLimits,
    *,
    joint: int | None = None,
    quantities: Sequence[str] = _QUANTITIES,
    rate: float = 1000.0,
) -> Any:
    """Position, velocity, acceleration and jerk of one joint, each against its limits.

    Args:
        trajectories: One plan, or several by label (e.g. one per planner) on one time axis.
        limits: The limits to draw (dashed): position bounds, +-velocity, ...
        joint: Joint index; the one that comes nearest to (or beyond) its velocity limit in
            any plan when None.
        quantities: Panels, a subset of position, velocity, acceleration, jerk.
        rate: Sampling rate [Hz] (breakpoints are always included).

    Returns:
        The matplotlib figure, one panel per quantity.

    Raises:
        InvalidInputError: No trajectories, joint counts that differ from the limits', or a
            joint index out of range.
        UnknownNameError: An unknown quantity.
        MissingDependencyError: matplotlib is not installed.
    """
    named = _named(trajectories)
    for label, trajectory in named.items():
        if trajectory.dof != limits.n:
            raise InvalidInputError(
                f"trajectory {label!r} has {trajectory.dof} joints, the limits {limits.n}",
                name="trajectories",
            )
    wanted = _quantities(quantities)
    samples = {label: _samples(t, rate) for label, t in named.items()}
    joint = _joint(joint, samples, limits)
    plt = pyplot()
    figure, axes = plt.subplots(
        len(wanted), 1, sharex=True, figsize=(8.0, 2.2 * len(wanted)), constrained_layout=True
    )
    axes = np.atleast_1d(axes)
    for ax, quantity in zip(axes, wanted, strict=True):
        _panel(ax, quantity, samples, limits, joint)
    axes[0].set_title(f"joint {limits.names[joint]!r} (dashed: its limits)")
    axes[0].legend(loc="best", fontsize="small")
    axes[-1].set_xlabel("time [s]")
    return figure


def _quantities(quantities: Sequence[str]) -> list[str]:
    """The panels asked for, each a known quantity, in order."""
    if isinstance(quantities, str):  # would be iterated letter by letter
        raise InvalidInputError(
            f"quantities must be a sequence of names, got {quantities!r}; "
            f"write ({quantities!r},) for one",
            name="quantities",
        )
    wanted = list(quantities)
    for quantity in wanted:
        as_choice(quantity, "plotted quantity", _QUANTITIES)
    return wanted


def _joint(joint: int | None, samples: Mapping[str, TrajectorySample], limits: JointLimits) -> int:
    """The joint index asked for, checked; when None, the one nearest its velocity limit."""
    if joint is None:
        ratios = [np.max(np.abs(s.qd), axis=0) / limits.velocity for s in samples.values()]
        return int(np.argmax(np.max(ratios, axis=0)))
    if isinstance(joint, bool) or not isinstance(joint, (int, np.integer)):
        raise InvalidInputError(f"joint must be an integer index, got {joint!r}", name="joint")
    if not 0 <= joint < limits.n:
        raise InvalidInputError(f"joint must be in [0, {limits.n - 1}], got {joint}", name="joint")
    return joint


def _panel(
    ax: Any, quantity: str, samples: Mapping[str, TrajectorySample], limits: JointLimits, joint: int
) -> None:
    """One quantity of one joint in every sample, its limits dashed."""
    for label, sample in samples.items():
        ax.plot(sample.t, getattr(sample, _FIELD[quantity])[:, joint], label=label)
    if quantity == "position":
        bounds = (limits.lower[joint], limits.upper[joint])
    else:
        value = getattr(limits, _LIMIT[quantity])[joint]
        bounds = (-value, value)
    for bound in bounds:
        ax.axhline(bound, color="k", linestyle="--", linewidth=0.8)
    ax.set_ylabel(f"{quantity} [{limits.unit(quantity, joint)}]")


def plot_tool_speed(
    robot: Robot,
    trajectories: Trajectory | Mapping[str, Trajectory],
    *,
    rate: float = 500.0,
) -> Any:
    """Speed of the tool frame origin over time, the strike phase shaded.

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
    named = _named(trajectories)
    plt = pyplot()
    figure, ax = plt.subplots(figsize=(8.0, 3.5), constrained_layout=True)
    for label, trajectory in named.items():
        if trajectory.dof != robot.dof:
            raise InvalidInputError(
                f"trajectory {label!r} has {trajectory.dof} joints, robot {robot.name!r} "
                f"has {robot.dof}",
                name="trajectories",
            )
        sample = _samples(trajectory, rate)
        speed = np.linalg.norm(
            np.einsum("mij,mj->mi", robot.jacobian(sample.q)[:, :3], sample.qd), axis=1
        )
        ax.plot(sample.t, speed, label=label)
        for phase in trajectory.phases:
            if phase.name == "strike":
                ax.axvspan(phase.t_start, phase.t_end, color="0.9", zorder=0)
    ax.set_xlabel("time [s] (grey: strike phase)")
    ax.set_ylabel(f"tool speed [m/s] ({robot.tool_frame})")
    ax.legend(loc="best", fontsize="small")
    return figure


def joint_origins(robot: Robot, q: FloatArray) -> FloatArray:
    """World positions of the base, every joint and the tool frame [m], shape (n + 2, 3)."""
    data = robot.data
    pin.forwardKinematics(robot.model, data, q)
    points = [np.zeros(3)]
    points += [np.array(data.oMi[i].translation) for i in range(1, robot.model.njoints)]
    points.append(
        np.array(pin.updateFramePlacement(robot.model, data, robot.tool_frame_id).translation)
    )
    return np.array(points)


#: Most stick figures :func:`plot_robot` draws: each is one forward-kinematics pass and one
#: line, and far fewer already fill a view.
MAX_FIGURES = 1000


def plot_robot(robot: Robot, trajectory: Trajectory, *, count: int = 8, ax: Any = None) -> Any:
    """The arm as stick figures at ``count`` instants, with the tool path (static 3-D view).

    A headless stand-in for an animation: the links are drawn from joint origin to joint
    origin, lighter early and darker late.

    Args:
        robot: The robot.
        trajectory: Its plan.
        count: Instants drawn, evenly spaced in time, >= 2.
        ax: A matplotlib 3-D axes to draw into; a new figure when None.

    Returns:
        The matplotlib figure.

    Raises:
        InvalidInputError: A count below 2, or a trajectory for another joint count.
        MissingDependencyError: matplotlib is not installed.
    """
    count = as_count(count, "count", 2, maximum=MAX_FIGURES)
    if trajectory.dof != robot.dof:
        raise InvalidInputError(
            f"the trajectory has {trajectory.dof} joints, robot {robot.name!r} has {robot.dof}",
            name="trajectory",
        )
    plt = pyplot()
    if ax is None:
        figure = plt.figure(figsize=(6.5, 6.0), constrained_layout=True)
        ax = figure.add_subplot(projection="3d")
    else:
        figure = ax.figure
    instants = np.linspace(0.0, trajectory.duration, count)
    drawn = []
    for k, q in enumerate(trajectory.sample(instants).q):
        points = joint_origins(robot, q)
        shade = 0.75 - 0.6 * k / (count - 1)
        ax.plot(*points.T, "-o", color=str(shade), markersize=3, linewidth=2)
        drawn.append(points)
    path = robot.tool_position(trajectory.sample(trajectory.times(200.0)).q)
    ax.plot(*path.T, color="tab:red", linewidth=1.5, label="tool path")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(f"{robot.name}: {count} instants over {trajectory.duration:.2f} s")
    ax.legend(loc="upper left", fontsize="small")
    _equal_axes(ax, np.vstack([path, *drawn]))
    return figure


def _equal_axes(ax: Any, points: FloatArray) -> None:
    """Same scale on x, y and z around the drawn points."""
    centre = (points.max(axis=0) + points.min(axis=0)) / 2
    half = max(float(np.max(points.max(axis=0) - points.min(axis=0))) / 2, 0.1)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
