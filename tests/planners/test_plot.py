"""Tests of planners.plot: profiles of one joint, tool speed, the public names kept."""

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
    plans = {
        "cubic": planners.Cubic().plan(move),
        "LSPB": planners.LSPB().plan(move),
        "ruckig": planners.Ruckig().plan(move),
    }
    return robot, plans


def _curves(ax):
    return {line.get_label(): line for line in ax.lines if not line.get_label().startswith("_")}


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
    limits = sorted(line.get_ydata()[0] for line in velocity.lines if line.get_gid() == "limit")
    assert limits == pytest.approx([-robot.limits.velocity[joint], robot.limits.velocity[joint]])
    curve = _curves(velocity)["ruckig"]
    t = curve.get_xdata()
    np.testing.assert_allclose(curve.get_ydata(), plans["ruckig"].sample(t).qd[:, joint])
    position = sorted(line.get_ydata()[0] for line in axes[0].lines if line.get_gid() == "limit")
    assert position == pytest.approx([robot.limits.lower[joint], robot.limits.upper[joint]])


def test_an_lspb_jerk_is_drawn_unbounded_at_its_acceleration_jumps(moves):
    robot, plans = moves
    # the checker finds the jerk unbounded: the plot marks it at the checker's jump time
    finding = planners.check(plans["LSPB"], robot, quantities=["jerk"])["jerk"]
    assert finding.value == np.inf
    joint = robot.limits.names.index(finding.joint)
    figure = plot.plot_profiles(plans, robot.limits, joint=joint)
    acceleration, jerk = figure.axes[2], figure.axes[3]
    markers = [line for line in jerk.lines if line.get_label() == "LSPB: unbounded (jump)"]
    assert len(markers) == 1
    assert np.min(np.abs(np.asarray(markers[0].get_xdata()) - finding.time)) < 1e-12
    assert any("unbounded (jump)" in text.get_text() for text in jerk.texts)
    # the triangles sit on the panel's top edge, outside the data (axes coordinates >= 1)
    assert np.all(np.asarray(markers[0].get_ydata()) >= 1.0)
    # the LSPB acceleration curve is broken at each jump: no line joins the two sides
    curve = _curves(acceleration)["LSPB"]
    gaps = np.flatnonzero(np.isnan(curve.get_xdata()))
    assert len(gaps) == len(markers[0].get_xdata())
    # the smooth plans are never marked
    assert not [line for line in jerk.lines if line.get_label().startswith(("cubic:", "ruckig:"))]


def test_plans_get_distinct_styles_and_the_legend_sits_below_the_panels(moves):
    robot, plans = moves
    figure = plot.plot_profiles(plans, robot.limits)
    curves = _curves(figure.axes[1])
    looks = {
        (c.get_color(), str(c.get_linestyle()), c.get_marker(), c.get_linewidth())
        for c in (curves["cubic"], curves["LSPB"], curves["ruckig"])
    }
    assert len(looks) == 3
    assert len({curves[k].get_marker() for k in ("cubic", "LSPB", "ruckig")}) == 3
    assert len({curves[k].get_linewidth() for k in ("cubic", "LSPB", "ruckig")}) == 3
    figure.canvas.draw()
    (legend,) = figure.legends
    box = legend.get_window_extent()
    for ax in figure.axes:
        assert box.y1 <= ax.get_window_extent().y0  # below every panel: off the data
    assert {t.get_text() for t in legend.get_texts()} >= {"cubic", "LSPB", "ruckig", "limit"}


def test_tool_speed_matches_the_jacobian_and_shades_each_strike_in_its_colour(moves):
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
    struck = planners.Trajectory(
        [0.0, 0.5, 1.0],
        np.zeros((2, 2, 7)),
        phases=[planners.Phase("approach", 0.0, 0.5), planners.Phase("strike", 0.5, 1.0)],
    )
    figure = plot.plot_tool_speed(robot, {"ruckig": plans["ruckig"], "still": struck})
    (ax,) = figure.axes
    colour = _curves(ax)["still"].get_color()
    bands = [p for p in ax.patches if matplotlib.colors.same_color(p.get_facecolor()[:3], colour)]
    assert bands and all(p.get_x() == pytest.approx(0.5) for p in bands)


def test_the_public_names_stay_importable():
    for name in (
        "plot_profiles",
        "plot_tool_speed",
        "plot_robot",
        "joint_origins",
        "pyplot",
        "plot_trajectory",
        "plot_limit_fractions",
    ):
        assert callable(getattr(plot, name))


def test_trajectory_plot_method_draws_plot_trajectory(moves):
    # Trajectory.plot() is added beside this module; it calls plot_trajectory exactly.
    robot, plans = moves
    if not hasattr(planners.Trajectory, "plot"):
        pytest.skip("Trajectory.plot() is not in this tree")
    figure = plans["LSPB"].plot(limits=robot.limits)
    expected = plot.plot_trajectory(plans["LSPB"], limits=robot.limits)
    assert [ax.get_ylabel() for ax in figure.axes] == [ax.get_ylabel() for ax in expected.axes]
    assert any(line.get_label().endswith("unbounded (jump)") for line in figure.axes[3].lines)


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
    with pytest.raises(InvalidInputError, match="has 7 joints"):
        plot.plot_tool_speed(get_robot("paddle4"), plans)


def test_counts_and_names_are_checked():
    # issue 32, defects 6 and 7: a string was iterated letter by letter; counts are bounded
    robot = get_robot("paddle4")
    traj = planners.Cubic().plan(problems.PointToPoint(robot, robot.home, [0.5, 0.1, 0.2, 0.0]))
    with pytest.raises(InvalidInputError, match="quantities must be a sequence of names"):
        plot.plot_profiles(traj, robot.limits, quantities="velocity")
    with pytest.raises(InvalidInputError, match="count must be an integer <= 1000"):
        plot.plot_robot(robot, traj, count=10**6)
