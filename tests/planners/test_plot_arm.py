"""Tests of planners.plot_arm: stick figures of the arm, faded, in their scene."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners import plot_arm

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


def _sticks(figure):
    return [line for line in figure.axes[0].lines if line.get_gid() == "arm"]


def _lowest(ax):
    return min(np.min(np.array(line.get_data_3d())[2]) for line in ax.lines)


def test_stick_figures_end_at_the_tool_and_fade_from_early_to_late():
    robot = get_robot("sawyer")
    traj = planners.Cubic().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.3))
    figure = plot_arm.plot_robot(robot, traj, count=3)
    sticks = _sticks(figure)
    assert len(sticks) == 3
    end = np.array(sticks[-1].get_data_3d())[:, -1]
    np.testing.assert_allclose(end, robot.tool_position(traj.sample(traj.duration).q), atol=1e-12)
    alphas = [stick.get_alpha() for stick in sticks]
    assert alphas == sorted(alphas) and alphas[0] < 0.5 and alphas[-1] == 1.0
    # nothing below the floor: the view starts at the lowest point drawn
    assert figure.axes[0].get_zlim()[0] == pytest.approx(_lowest(figure.axes[0]), abs=1e-9)
    assert figure.legends  # the legend sits below the view, not on it


def test_a_pool_shot_is_drawn_with_its_table_and_the_floor_at_the_cloth():
    shot = problems.sawyer_pool_shot(speed=1.0)
    traj = planners.Cubic().plan(problems.PointToPoint(shot.robot, shot.q_start, shot.q_contact))
    figure = plot_arm.plot_robot(shot.robot, traj, count=4, problem=shot)
    ax = figure.axes[0]
    # the floor is the cloth, or lower where the arm goes lower (beside the table)
    cloth = float(shot.ball[2] - shot.ball_radius)
    assert ax.get_zlim()[0] == pytest.approx(min(cloth, _lowest(ax)), abs=1e-9)
    assert "strike line" in [line.get_label() for line in ax.lines]
    with pytest.raises(InvalidInputError, match="the trajectory has 7 joints"):
        plot_arm.plot_robot(get_robot("paddle4"), traj)
    with pytest.raises(InvalidInputError, match="count must be"):
        plot_arm.plot_robot(shot.robot, traj, count=1)
