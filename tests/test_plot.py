from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import controllers, physics, planners, problems
from optraj.controllers.plot import plot_tracking
from optraj.errors import InvalidInputError, UnknownNameError

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
    limit_lines = [line for line in joint_axes.lines if line.get_linestyle() == "--"]
    assert sorted(line.get_ydata()[0] for line in limit_lines) == pytest.approx(
        [-robot.limits.velocity[joint], robot.limits.velocity[joint]]
    )
    # The error curve is the distance between the realised and the planned tool positions.
    drawn = error_axes.lines[0].get_ydata()
    expected = 1e3 * np.linalg.norm(
        results[0].T_world_tool[:, :3, 3] - results[0].references.T_world_tool[:, :3, 3], axis=1
    )
    np.testing.assert_allclose(drawn, expected)


def test_plot_rejects_bad_arguments(runs):
    robot, results = runs
    with pytest.raises(InvalidInputError, match="joint must be in"):
        plot_tracking(results, robot.limits, joint=9)
    with pytest.raises(InvalidInputError, match=r"controllers\.Result"):
        plot_tracking([], robot.limits)


# ------------------------------------------------------------------ planners.plot


@pytest.fixture(scope="module")
def moves():
    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.3)
    return robot, {"cubic": planners.Cubic().plan(move), "ruckig": planners.Ruckig().plan(move)}


def test_profiles_draw_each_plan_against_the_limits_of_the_busiest_joint(moves):
    robot, plans = moves
    figure = planners.plot.plot_profiles(plans, robot.limits)
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
    figure = planners.plot.plot_tool_speed(robot, plans["ruckig"])
    (ax,) = figure.axes
    line = ax.lines[0]
    t = line.get_xdata()
    sample = plans["ruckig"].sample(t)
    expected = np.linalg.norm(
        np.einsum("mij,mj->mi", robot.jacobian(sample.q)[:, :3], sample.qd), axis=1
    )
    np.testing.assert_allclose(line.get_ydata(), expected, atol=1e-12)
    figure = planners.plot.plot_robot(robot, plans["cubic"], count=3)
    sticks = [line for line in figure.axes[0].lines if line.get_marker() == "o"]
    assert len(sticks) == 3
    # The last point of each stick figure is the tool frame origin.
    end = sticks[-1].get_data_3d()
    q_end = plans["cubic"].sample(plans["cubic"].duration).q
    np.testing.assert_allclose(np.array(end)[:, -1], robot.tool_position(q_end), atol=1e-12)


def test_planner_plots_reject_bad_arguments(moves):
    robot, plans = moves
    with pytest.raises(InvalidInputError, match="trajectories must be"):
        planners.plot.plot_profiles({}, robot.limits)
    with pytest.raises(InvalidInputError, match="joint must be in"):
        planners.plot.plot_profiles(plans, robot.limits, joint=7)
    with pytest.raises(UnknownNameError, match="quantity"):
        planners.plot.plot_profiles(plans, robot.limits, quantities=["torque"])
    with pytest.raises(InvalidInputError, match="has 7 joints"):
        planners.plot.plot_profiles(plans, get_robot("paddle4").limits)
    with pytest.raises(InvalidInputError, match="count must be"):
        planners.plot.plot_robot(robot, plans["cubic"], count=1)


# ------------------------------------------------------------------ physics.plot


@pytest.fixture(scope="module")
def balls():
    """Two straight shots (one 2 mm off the ball's centre) and one that misses the ball."""
    shot = problems.sawyer_pool_shot(1.0, heading_deg=10.0)
    scene = physics.scene_for(shot)
    lateral = np.array([-shot.direction[1], shot.direction[0], 0.0])

    def cue(offset):
        return physics.outcome(
            physics.straight_cue(scene, shot.direction, 1.0, offset=offset), shot
        )

    return [cue(0.0 * lateral), cue(2e-3 * lateral)], [cue(0.1 * lateral)]


def test_ball_paths_draw_each_ball_on_the_table_and_off_its_line(balls):
    hits, missed = balls
    figure = physics.plot_ball_paths({"straight": hits, "with a miss": [hits[0], *missed]})
    _, _, side, _ = figure.axes  # rows first: table, table, off-line, off-line
    assert figure.axes[1].get_title() == "with a miss: 2 shots, 1 missed"
    assert [line.get_marker() for line in figure.axes[1].lines].count("x") == 1
    assert len(side.lines) == 2 + 1  # one curve per ball, then the commanded line
    # The 2 mm offset turns the ball by asin(2 / 34.6) = 3.3 deg: about 120 mm off after the
    # 2.1 m to the far cushion; the straight ball stays on its line.
    offsets = [np.max(np.abs(line.get_ydata())) for line in side.lines[:2]]
    assert offsets[0] < 0.01 and 60.0 < offsets[1] < 200.0  # [mm]
    plt = matplotlib.pyplot
    plt.close(figure)


def test_heading_errors_are_drawn_as_shares_with_the_misses_counted(balls):
    hits, missed = balls
    figure = physics.plot_heading_errors({"straight": hits, "with a miss": [*hits, *missed]})
    ax = figure.axes[0]
    curves = [line for line in ax.lines if line.get_label() != "tolerance"]
    labels = [line.get_label() for line in curves]
    assert labels == ["straight", "with a miss (1 missed)"]
    # A miss never reaches the top: 2 of 3 shots at most.
    assert curves[0].get_ydata()[-1] == 1.0
    assert curves[1].get_ydata()[-1] == pytest.approx(2 / 3)
    matplotlib.pyplot.close(figure)


def test_ball_plots_reject_bad_arguments(balls):
    hits, _ = balls
    with pytest.raises(InvalidInputError, match="non-empty"):
        physics.plot_ball_paths({})
    with pytest.raises(InvalidInputError, match=r"physics\.Outcome"):
        physics.plot_heading_errors({"runs": ["not an outcome"]})
    with pytest.raises(InvalidInputError, match=r"outcomes\['runs'\]\[1\] must be"):
        physics.plot_heading_errors({"runs": [hits[0], 3.0]})
    with pytest.raises(InvalidInputError, match="labels must be strings"):
        physics.plot_heading_errors({1: hits})
    broken = dataclasses.replace(hits[0], heading_error=float("nan"))
    with pytest.raises(InvalidInputError, match="non-finite"):
        physics.plot_heading_errors({"runs": [broken]})
    with pytest.raises(InvalidInputError, match="ax must be"):
        physics.plot_heading_errors({"runs": hits}, ax="axes")


def test_ball_paths_refuse_a_paddle_outcome():
    strike = problems.PaddleStrike(
        problems.seed_paddle_strike().robot, ball=(0.8, 0.2, 0.3), speed=0.5
    )
    scene = physics.scene_for(strike)
    paddle = physics.outcome(physics.straight_cue(scene, strike.normal, 0.5), strike)
    assert paddle.hit and paddle.kind == "paddle"
    with pytest.raises(InvalidInputError, match="'paddle' outcome"):
        physics.plot_ball_paths({"paddle": [paddle]})


def test_counts_and_names_are_checked():
    # issue 32, defects 6 and 7: a string was iterated letter by letter; counts are bounded
    robot = get_robot("paddle4")
    traj = planners.Cubic().plan(problems.PointToPoint(robot, robot.home, [0.5, 0.1, 0.2, 0.0]))
    with pytest.raises(InvalidInputError, match="quantities must be a sequence of names"):
        planners.plot.plot_profiles(traj, robot.limits, quantities="velocity")
    with pytest.raises(InvalidInputError, match="count must be an integer <= 1000"):
        planners.plot.plot_robot(robot, traj, count=10**6)
