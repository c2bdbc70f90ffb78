"""Tests of planners.plot_jumps: the checker's jumps, broken curves, unbounded markers."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.planners import plot_jumps, plot_style

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def paddle():
    robot = get_robot("paddle4")
    move = problems.PointToPoint(robot, robot.home, [0.6, 0.4, 0.3, 0.2])
    return robot, planners.LSPB().plan(move), planners.Quintic().plan(move)


def test_jump_times_are_the_checkers_jumps(paddle):
    robot, lspb, quintic = paddle
    jumps, unbounded = plot_jumps.jump_times(lspb, robot.limits)
    assert "velocity" not in jumps and "position" not in jumps
    # LSPB's acceleration jumps at its blends: the jerk is unbounded there, the torque jumps
    assert "torque" not in unbounded
    for joint, times in jumps["acceleration"].items():
        assert unbounded["jerk"][joint] == times == jumps["torque"][joint]
        assert set(times) <= set(np.asarray(lspb.breakpoints).tolist())
    report = planners.check(lspb, robot, quantities=["jerk"])
    joint = robot.limits.names.index(report["jerk"].joint)
    assert report["jerk"].time in unbounded["jerk"][joint]
    assert plot_jumps.any_joint(unbounded, "jerk") == sorted(
        {t for ts in unbounded["jerk"].values() for t in ts}
    )
    assert plot_jumps.jump_times(quintic, robot.limits) == ({}, {})
    assert planners.check(quintic, robot, quantities=["jerk"])["jerk"].value < np.inf


def test_broken_curve_puts_a_gap_between_the_two_sides_of_a_jump():
    t = np.array([0.0, 0.5, 1.0 - 1e-9, 1.0, 1.5])
    y = np.array([0.0, 0.0, 0.0, 2.0, 2.0])
    bt, by = plot_jumps.broken_curve(t, y, [1.0])
    assert np.isnan(bt[3]) and np.isnan(by[3])
    np.testing.assert_array_equal(np.delete(by, 3), y)
    _, same_y = plot_jumps.broken_curve(t, y, [])
    np.testing.assert_array_equal(same_y, y)
    columns = plot_jumps.broken_curve(t, np.column_stack([y, y]), [1.0, 0.0])[1]
    assert columns.shape == (6, 2)  # a jump at the first sample has nothing to break


def test_markers_sit_above_the_data_in_rows_with_a_note():
    plt = plot_style.pyplot()
    figure, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    style = plot_style.line_style(2)
    first = plot_jumps.mark_unbounded(ax, [0.5, 0.25, 0.5], style, "A")
    second = plot_jumps.mark_unbounded(ax, [0.5], style, "B", row=1, note=None)
    marker = first[0]
    assert marker.get_label() == "A: unbounded (jump)"
    np.testing.assert_allclose(marker.get_xdata(), [0.25, 0.5])
    assert np.all(np.asarray(marker.get_ydata()) == 1.0)
    assert np.all(np.asarray(second[0].get_ydata()) > 1.0)
    assert [t.get_text() for t in ax.texts] == ["unbounded (jump)"]
    assert plot_jumps.mark_unbounded(ax, [], style, "C") == []
    _, labels = plot_jumps.legend_entries([ax])
    assert labels.count("unbounded (jump)") == 1
    plt.close(figure)
