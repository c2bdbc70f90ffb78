"""The arm in 3-D: a few poses along a plan as stick figures, the tool path and the scene.

>>> figure = plot_robot(robot, traj, count=4, problem=shot)   # table, ball and strike line
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.planners.plot_scene import draw_scene, floor_height, scene_points, view_box
from optraj.planners.plot_style import pyplot
from optraj.planners.trajectory import Trajectory, fitted_to
from optraj.robots import Robot
from optraj.validation import as_count

__all__ = ["MAX_FIGURES", "joint_origins", "plot_robot"]

FloatArray = NDArray[np.float64]

#: Most stick figures :func:`plot_robot` draws: each is one forward-kinematics pass and one
#: line, and far fewer already fill a view.
MAX_FIGURES = 1000
#: Opacity of the earliest and of the last pose: earlier poses fade so that the last reads.
FIRST_ALPHA = 0.3
LAST_ALPHA = 1.0
#: Colour of the arm's poses, light (early) to dark (last).
ARM_COLOURS = ("#6baed6", "#08306b")


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


def plot_robot(
    robot: Robot,
    trajectory: Trajectory,
    *,
    count: int = 8,
    ax: Any = None,
    problem: object = None,
) -> Any:
    """The arm as stick figures at ``count`` instants, with the tool path (static 3-D view).

    A headless stand-in for an animation: the links are drawn from joint origin to joint
    origin, early poses pale and transparent, the last one dark and opaque, so that a few
    poses read even where they overlap (3 to 5 read best). With a problem, its scene is drawn
    too: a pool shot's table, ball, strike line and heading; a pick-and-place's blocks and
    their places on the pile. The view has one scale on all axes and its floor at the
    surface the task rests on: nothing is drawn below it.

    Args:
        robot: The robot.
        trajectory: Its plan.
        count: Instants drawn, evenly spaced in time, >= 2.
        ax: A matplotlib 3-D axes to draw into; a new figure when None.
        problem: The problem the plan is for (:class:`problems.PoolStrike` or
            :class:`problems.PickAndPlace` draw a scene); None for the arm alone.

    Returns:
        The matplotlib figure.

    Raises:
        InvalidInputError: A count below 2, or a trajectory for another joint count.
        MissingDependencyError: matplotlib is not installed.
    """
    count = as_count(count, "count", 2, maximum=MAX_FIGURES)
    fitted_to(trajectory, robot)
    plt = pyplot()
    if ax is None:
        figure = plt.figure(figsize=(7.0, 6.4), layout="constrained")
        ax = figure.add_subplot(projection="3d")
    else:
        figure = ax.figure
    instants = np.linspace(0.0, trajectory.duration, count)
    poses = [joint_origins(robot, q) for q in trajectory.sample(instants).q]
    path = robot.tool_position(trajectory.sample(trajectory.times(200.0)).q)
    points = np.vstack([path, *poses, scene_points(problem)])
    view = view_box(points, floor_height(problem, points))
    draw_scene(ax, problem, view)
    _poses(ax, poses, instants)
    ax.plot(*path.T, color="#d62728", linewidth=1.5, label="tool path", zorder=2.5)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(
        f"{robot.name}: {count} poses over {trajectory.duration:.2f} s (pale: early, dark: last)",
        fontsize="medium",
    )
    view.apply(ax)
    ax.view_init(elev=22.0, azim=-60.0)
    figure.legend(
        *ax.get_legend_handles_labels(),
        loc="outside lower center",
        ncols=4,
        fontsize="small",
        frameon=False,
    )
    return figure


def _poses(ax: Any, poses: list[FloatArray], instants: FloatArray) -> None:
    """Stick figures, pale and transparent early to dark and opaque last."""
    from matplotlib.colors import to_rgb

    early, late = (np.array(to_rgb(c)) for c in ARM_COLOURS)
    last = len(poses) - 1
    for k, points in enumerate(poses):
        share = k / last
        colour = tuple((1 - share) * early + share * late)
        alpha = FIRST_ALPHA + (LAST_ALPHA - FIRST_ALPHA) * share**1.5
        label = f"arm at t = {instants[k]:.2f} s" if k in (0, last) else None
        ax.plot(
            *points.T,
            "-o",
            color=colour,
            alpha=alpha,
            markersize=3.5,
            linewidth=1.5 + 1.5 * share,
            label=label,
            gid="arm",
            zorder=2.0,
        )
