"""Tests of planners.plot_fractions: every joint as a fraction of its limit."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners import plot_fractions

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def paddle():
    robot = get_robot("paddle4")
    move = problems.PointToPoint(robot, robot.home, [0.6, 0.4, 0.3, 0.2])
    return robot, {"LSPB": planners.LSPB().plan(move), "quintic": planners.Quintic().plan(move)}


def _joint_lines(ax, names):
    return {line.get_label(): line for line in ax.lines if line.get_label() in names}


def test_fractions_are_the_quantities_over_their_limits(paddle):
    robot, plans = paddle
    limits = robot.limits
    sample = plans["quintic"].sample(np.linspace(0.0, plans["quintic"].duration, 7))
    velocity = plot_fractions.limit_fractions(sample, limits, "velocity")
    np.testing.assert_allclose(velocity, np.abs(sample.qd) / limits.velocity, rtol=1e-15)
    middle = (limits.upper + limits.lower) / 2
    position = plot_fractions.limit_fractions(sample, limits, "position")
    np.testing.assert_allclose(position, np.abs(sample.q - middle) / (limits.upper - middle))
    at_bounds = sample._replace(q=np.vstack([limits.lower, limits.upper]))
    np.testing.assert_allclose(plot_fractions.limit_fractions(at_bounds, limits, "position"), 1.0)
    torque = plot_fractions.limit_fractions(sample, limits, "torque", robot)
    expected = np.abs(robot.inverse_dynamics(sample.q, sample.qd, sample.qdd)) / limits.effort
    np.testing.assert_allclose(torque, expected, rtol=1e-12)


def test_one_panel_per_quantity_and_plan_with_the_limit_at_one(paddle):
    robot, plans = paddle
    figure = plot_fractions.plot_limit_fractions(plans, robot.limits, robot=robot, rate=200.0)
    axes = np.array(figure.axes).reshape(5, 2)
    names = robot.limits.names
    for ax in axes.flat:
        (limit,) = [line for line in ax.lines if line.get_gid() == "limit"]
        assert list(limit.get_ydata()) == [1.0, 1.0]
        assert set(_joint_lines(ax, names)) == set(names)
    assert "jerk" in axes[3, 0].get_ylabel() and "torque" in axes[4, 0].get_ylabel()
    lines = _joint_lines(axes[1, 1], names)  # velocity of the quintic
    curve = lines[names[2]]
    t = np.asarray(curve.get_xdata())
    expected = np.abs(plans["quintic"].sample(t).qd[:, 2]) / robot.limits.velocity[2]
    np.testing.assert_allclose(curve.get_ydata(), expected, rtol=1e-12)
    # LSPB's jerk is unbounded: marked on its panel, never on the quintic's
    assert any(line.get_label().endswith("unbounded (jump)") for line in axes[3, 0].lines)
    assert not any(line.get_label().endswith("unbounded (jump)") for line in axes[3, 1].lines)


def test_without_a_robot_there_is_no_torque_row(paddle):
    robot, plans = paddle
    figure = plot_fractions.plot_limit_fractions(plans["quintic"], robot.limits, rate=200.0)
    assert len(figure.axes) == 4
    figure.canvas.draw()
    (legend,) = figure.legends
    assert legend.get_window_extent().y1 <= figure.axes[-1].get_window_extent().y0
    with pytest.raises(InvalidInputError, match="torque row needs the robot"):
        plot_fractions.plot_limit_fractions(plans, robot.limits, quantities=["torque"])
    with pytest.raises(UnknownNameError, match="snap"):
        plot_fractions.plot_limit_fractions(plans, robot.limits, quantities=["snap"])
    with pytest.raises(InvalidInputError, match="robot 'sawyer' has 7 joints, the limits 4"):
        plot_fractions.plot_limit_fractions(plans, robot.limits, robot=get_robot("sawyer"))
