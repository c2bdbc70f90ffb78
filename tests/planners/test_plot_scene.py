"""Tests of planners.plot_scene: the table, ball, strike line and blocks around the arm."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import physics, problems
from optraj.planners import plot_scene, plot_style

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def shot():
    return problems.sawyer_pool_shot(speed=1.0)


def _axes3d():
    plt = plot_style.pyplot()
    figure = plt.figure()
    return figure, figure.add_subplot(projection="3d")


def test_view_box_is_a_cube_standing_on_the_floor():
    points = np.array([[0.0, 0.0, 0.1], [0.4, 0.2, 0.5]])
    box = plot_scene.view_box(points, floor=-0.05)
    assert box.low[2] == -0.05
    sides = box.high - box.low
    np.testing.assert_allclose(sides, sides[0])
    assert np.all(box.low <= points.min(axis=0)) and np.all(box.high >= points.max(axis=0))


def test_a_pool_shot_draws_cloth_ball_strike_line_and_heading(shot):
    figure, ax = _axes3d()
    points = np.vstack([np.zeros((1, 3)), plot_scene.scene_points(shot)])
    floor = plot_scene.floor_height(shot, points)
    cloth = float(physics.pool_scene(shot.robot, shot.ball).table_height)
    assert floor == pytest.approx(min(cloth, points[:, 2].min()))
    box = plot_scene.view_box(points, floor)
    plot_scene.draw_scene(ax, shot, box)
    labels = [artist.get_label() for artist in [*ax.lines, *ax.collections]]
    assert {"strike line", "contact point", "table cloth", "ball heading"} <= set(labels)
    (line,) = [line for line in ax.lines if line.get_label() == "strike line"]
    ends = np.array(line.get_data_3d()).T
    np.testing.assert_allclose(ends, [shot.entry_point, shot.exit_point])
    plot_style.pyplot().close(figure)


def test_pick_and_place_draws_each_block_and_its_place_on_the_pile():
    problem = problems.youbot_two_blocks()
    figure, ax = _axes3d()
    points = plot_scene.scene_points(problem)
    assert len(points) == 2 * problem.count
    floor = plot_scene.floor_height(problem, points)
    assert floor == pytest.approx(np.min(problem.picks[:, 2]) - problem.block_height / 2)
    plot_scene.draw_scene(ax, problem, plot_scene.view_box(points, floor))
    labels = [c.get_label() for c in ax.collections]
    assert labels.count("block") == 1 and labels.count("on the pile") == 1
    assert len(ax.collections) == 1 + 2 * problem.count  # the floor and two cubes per block
    plot_style.pyplot().close(figure)


def test_without_a_problem_only_a_floor():
    figure, ax = _axes3d()
    assert plot_scene.scene_points(None).shape == (0, 3)
    points = np.array([[0.0, 0.0, -0.2], [0.3, 0.1, 0.4]])
    assert plot_scene.floor_height(None, points) == -0.2
    plot_scene.draw_scene(ax, None, plot_scene.view_box(points, -0.2))
    assert len(ax.collections) == 1
    plot_style.pyplot().close(figure)
