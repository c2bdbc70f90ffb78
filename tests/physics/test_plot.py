"""Tests of physics.plot: ball paths and heading errors."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj import physics, problems
from optraj.errors import InvalidInputError, UnknownNameError

matplotlib = pytest.importorskip("matplotlib")  # optraj[examples]
matplotlib.use("Agg")  # headless; plotting imports pyplot only when called


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
    # each label a style of its own, the legend below the axes, off the data
    assert curves[0].get_linestyle() != curves[1].get_linestyle() or (
        curves[0].get_marker() != curves[1].get_marker()
    )
    assert curves[0].get_color() != curves[1].get_color()
    figure.canvas.draw()
    (legend,) = figure.legends
    assert legend.get_window_extent().y1 <= ax.get_window_extent().y0
    matplotlib.pyplot.close(figure)


def test_heading_errors_on_given_axes_keep_the_legend_outside_or_leave_it(balls):
    hits, _ = balls
    figure, (left, right) = matplotlib.pyplot.subplots(1, 2, layout="constrained")
    physics.plot_heading_errors({"straight": hits}, ax=left)
    physics.plot_heading_errors({"straight": hits}, ax=right, legend="none")
    figure.canvas.draw()
    box = left.get_legend().get_window_extent()
    assert box.x0 >= left.get_window_extent().x1  # right of the axes
    assert right.get_legend() is None
    with pytest.raises(UnknownNameError, match="legend"):
        physics.plot_heading_errors({"straight": hits}, ax=right, legend="top")
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
        problems.ece486_paddle_strike().robot, ball=(0.8, 0.2, 0.3), speed=0.5
    )
    scene = physics.scene_for(strike)
    paddle = physics.outcome(physics.straight_cue(scene, strike.normal, 0.5), strike)
    assert paddle.hit and paddle.kind == "paddle"
    with pytest.raises(InvalidInputError, match="'paddle' outcome"):
        physics.plot_ball_paths({"paddle": [paddle]})
