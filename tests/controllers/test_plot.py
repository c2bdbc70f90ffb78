"""Tests of controllers.plot: tracking runs against the limits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import controllers, planners, problems
from optraj.controllers.plot import plot_tracking
from optraj.errors import InvalidInputError

matplotlib = pytest.importorskip("matplotlib")  # optraj[examples]
matplotlib.use("Agg")  # headless; plotting imports pyplot only when called


@pytest.fixture(scope="module")
def runs():
    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.3)
    traj = planners.Ruckig().plan(move)  # at the speed limits: the commands go over them
    return robot, [
        controllers.simulate(robot, traj, make(robot), plant="kinematic")
        for make in (controllers.PseudoInversePID, controllers.DiffIKQP)
    ]


def test_plot_draws_each_run_and_the_limits(runs):
    robot, results = runs
    figure = plot_tracking(results, robot.limits)
    error_axes, _, joint_axes = figure.axes
    assert len(error_axes.lines) == 2
    # The joint panel shows the commands of the joint nearest its limit, and the limit lines.
    ratios = np.max([np.max(np.abs(r.command) / robot.limits.velocity, axis=0) for r in results], 0)
    joint = int(np.argmax(ratios))
    assert robot.limits.names[joint] in joint_axes.get_ylabel()
    limit_lines = [line for line in joint_axes.lines if line.get_gid() == "limit"]
    assert sorted(line.get_ydata()[0] for line in limit_lines) == pytest.approx(
        [-robot.limits.velocity[joint], robot.limits.velocity[joint]]
    )
    # The error curve is the distance between the realised and the planned tool positions.
    drawn = error_axes.lines[0].get_ydata()
    expected = 1e3 * np.linalg.norm(
        results[0].T_world_tool[:, :3, 3] - results[0].references.T_world_tool[:, :3, 3], axis=1
    )
    np.testing.assert_allclose(drawn, expected)


def test_runs_are_told_apart_and_the_legend_is_off_the_data(runs):
    robot, results = runs
    figure = plot_tracking([results[0], results[1], results[1]], robot.limits)
    error_axes = figure.axes[0]
    looks = {
        (line.get_color(), line.get_marker(), line.get_linewidth()) for line in error_axes.lines
    }
    assert len(looks) == 3
    labels = [line.get_label() for line in error_axes.lines]
    assert labels[1].startswith(f"{results[1].controller} (1)")
    assert labels[2].startswith(f"{results[1].controller} (2)")
    figure.canvas.draw()
    (legend,) = figure.legends
    assert legend.get_window_extent().y1 <= figure.axes[-1].get_window_extent().y0
    assert "speed limit" in [text.get_text() for text in legend.get_texts()]


def test_plot_rejects_bad_arguments(runs):
    robot, results = runs
    with pytest.raises(InvalidInputError, match="joint must be in"):
        plot_tracking(results, robot.limits, joint=9)
    with pytest.raises(InvalidInputError, match=r"controllers\.Result"):
        plot_tracking([], robot.limits)
