"""Tests of planners.plot_trajectory: every joint of one plan (behind Trajectory.plot())."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners import plot_style
from optraj.planners.plot_trajectory import plot_trajectory, scale_limits

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def lspb():
    robot = get_robot("paddle4")
    move = problems.PointToPoint(robot, robot.home, [0.6, 0.4, 0.3, 0.2])
    return robot, planners.LSPB().plan(move)


def test_every_joint_is_a_curve_with_its_limits_and_the_jerk_is_unbounded(lspb):
    robot, traj = lspb
    figure = plot_trajectory(traj, limits=robot.limits)
    position, velocity, _, jerk = figure.axes
    names = list(traj.joint_names)
    curves = {line.get_label(): line for line in velocity.lines if line.get_label() in names}
    assert list(curves) == names
    t = np.asarray(curves[names[1]].get_xdata())
    np.testing.assert_allclose(curves[names[1]].get_ydata(), traj.sample(t).qd[:, 1])
    limits = sorted(line.get_ydata()[0] for line in velocity.lines if line.get_gid() == "limit")
    expected = sorted([*robot.limits.velocity, *-robot.limits.velocity])
    np.testing.assert_allclose(limits, expected)
    assert any(line.get_label().endswith("unbounded (jump)") for line in jerk.lines)
    assert any(text.get_text() == "unbounded (jump)" for text in jerk.texts)
    assert position.get_ylabel() == "position [rad or m]"  # paddle4 mixes P and R joints
    assert "move" in [text.get_text() for text in position.texts]


def test_without_limits_jumps_are_judged_on_the_plans_own_scale(lspb):
    _, traj = lspb
    figure = plot_trajectory(traj, quantities=("acceleration", "jerk"))
    assert [ax.get_ylabel() for ax in figure.axes] == [
        "acceleration [rad/s^2 or m/s^2]",
        "jerk [rad/s^3 or m/s^3]",
    ]
    assert not [line for line in figure.axes[1].lines if line.get_gid() == "limit"]
    assert any(line.get_label().endswith("unbounded (jump)") for line in figure.axes[1].lines)
    own = scale_limits(traj, traj.sample(traj.times()))
    assert np.all(own.velocity > 1.0) and own.n == traj.dof


def test_draws_into_given_axes_with_extra_line_options(lspb):
    _, traj = lspb
    plt = plot_style.pyplot()
    figure, ax = plt.subplots()
    assert plot_trajectory(traj, quantities=["velocity"], ax=ax, linewidth=0.5) is figure
    assert {line.get_linewidth() for line in ax.lines if not line.get_label().startswith("_")} == {
        0.5
    }
    with pytest.raises(InvalidInputError, match="one per quantity"):
        plot_trajectory(traj, ax=ax)
    plt.close(figure)


def test_bad_input_is_refused(lspb):
    _, traj = lspb
    with pytest.raises(InvalidInputError, match=r"must be a planners\.Trajectory"):
        plot_trajectory({"a": traj})
    with pytest.raises(InvalidInputError, match="4 joints, the limits 7"):
        plot_trajectory(traj, limits=get_robot("sawyer").limits)
    with pytest.raises(UnknownNameError, match="torque"):
        plot_trajectory(traj, quantities=["torque"])
