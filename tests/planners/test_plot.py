"""Tests of planners.plot: profiles, tool speed and stick figures."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners import plot

matplotlib = pytest.importorskip("matplotlib")  # optraj[examples]
matplotlib.use("Agg")  # headless; plotting imports pyplot only when called


@pytest.fixture(scope="module")
def moves():
    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.3)
    return robot, {"cubic": planners.Cubic().plan(move), "ruckig": planners.Ruckig().plan(move)}


def test_profiles_draw_each_plan_against_the_limits_of_the_busiest_joint(moves):
    robot, plans = moves
    figure = plot.plot_profiles(plans, robot.limits)
    axes = figure.axes
    assert [ax.get_ylabel().split(" [")[0] for ax in axes] == [
        "position",
        "velocity",
        "acceleration",
        "jerk",
    ]
    ratios = [
        np.max(np.abs(t.sample(t.times()).qd), 0) / robot.limits.velocity for t in plans.values()
    ]
    joint = int(np.argmax(np.max(ratios, axis=0)))
    assert robot.limits.names[joint] in axes[0].get_title()
    velocity = axes[1]
    curves = [line for line in velocity.lines if line.get_linestyle() == "-"]
    dashed = sorted(line.get_ydata()[0] for line in velocity.lines if line.get_linestyle() == "--")
    assert len(curves) == 2
    assert dashed == pytest.approx([-robot.limits.velocity[joint], robot.limits.velocity[joint]])
    ruckig = plans["ruckig"]
    t = curves[1].get_xdata()
    np.testing.assert_allclose(curves[1].get_ydata(), ruckig.sample(t).qd[:, joint])
    position = sorted(line.get_ydata()[0] for line in axes[0].lines if line.get_linestyle() == "--")
    assert position == pytest.approx([robot.limits.lower[joint], robot.limits.upper[joint]])


def test_tool_speed_and_stick_figures(moves):
    robot, plans = moves
    figure = plot.plot_tool_speed(robot, plans["ruckig"])
    (ax,) = figure.axes
    line = ax.lines[0]
    t = line.get_xdata()
    sample = plans["ruckig"].sample(t)
    expected = np.linalg.norm(
        np.einsum("mij,mj->mi", robot.jacobian(sample.q)[:, :3], sample.qd), axis=1
    )
    np.testing.assert_allclose(line.get_ydata(), expected, atol=1e-12)
    figure = plot.plot_robot(robot, plans["cubic"], count=3)
    sticks = [line for line in figure.axes[0].lines if line.get_marker() == "o"]
    assert len(sticks) == 3
    # The last point of each stick figure is the tool frame origin.
    end = sticks[-1].get_data_3d()
    q_end = plans["cubic"].sample(plans["cubic"].duration).q
    np.testing.assert_allclose(np.array(end)[:, -1], robot.tool_position(q_end), atol=1e-12)


def test_planner_plots_reject_bad_arguments(moves):
    robot, plans = moves
    with pytest.raises(InvalidInputError, match="trajectories must be"):
        plot.plot_profiles({}, robot.limits)
    with pytest.raises(InvalidInputError, match="joint must be in"):
        plot.plot_profiles(plans, robot.limits, joint=7)
    with pytest.raises(UnknownNameError, match="quantity"):
        plot.plot_profiles(plans, robot.limits, quantities=["torque"])
    with pytest.raises(InvalidInputError, match="has 7 joints"):
        plot.plot_profiles(plans, get_robot("paddle4").limits)
    with pytest.raises(InvalidInputError, match="count must be"):
        plot.plot_robot(robot, plans["cubic"], count=1)


def test_counts_and_names_are_checked():
    # issue 32, defects 6 and 7: a string was iterated letter by letter; counts are bounded
    robot = get_robot("paddle4")
    traj = planners.Cubic().plan(problems.PointToPoint(robot, robot.home, [0.5, 0.1, 0.2, 0.0]))
    with pytest.raises(InvalidInputError, match="quantities must be a sequence of names"):
        plot.plot_profiles(traj, robot.limits, quantities="velocity")
    with pytest.raises(InvalidInputError, match="count must be an integer <= 1000"):
        plot.plot_robot(robot, traj, count=10**6)
