"""Tests of planners.time_optimal.phase_plane_plot: the phase plane drawn."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners
from optraj.errors import InvalidInputError
from optraj.planners.time_optimal.phase_plane import phase_plane
from optraj.planners.time_optimal.phase_plane_plot import plot_phase_plane

matplotlib = pytest.importorskip("matplotlib")  # optraj[examples]
matplotlib.use("Agg")  # headless; plotting imports pyplot only when called


def _plane(waypoints, robot):
    toppra = planners.Toppra(gridpoints=60)
    problem = toppra.build(np.asarray(waypoints), robot.limits, robot=robot)
    return phase_plane(problem, toppra.solve(problem))


@pytest.fixture(scope="module")
def line_plane():
    robot = get_robot("sawyer")
    return _plane([robot.home, robot.home + 0.4], robot)


@pytest.fixture(scope="module")
def curve_plane():
    robot = get_robot("sawyer")
    return _plane(
        [robot.home, robot.home + 0.4, robot.home + np.array([0.8, 0.0, 0.8, 0.0, 0.8, 0.0, 0.8])],
        robot,
    )


def _lines(figure):
    return {line.get_label(): line for line in figure.axes[0].lines}


def test_the_plan_and_every_bound_are_drawn_with_their_labels(curve_plane):
    plane = curve_plane
    figure = plot_phase_plane(plane)
    lines = _lines(figure)
    np.testing.assert_array_equal(lines["TOPPRA's plan"].get_ydata(), plane.sd)
    np.testing.assert_array_equal(lines["TOPPRA's plan"].get_xdata(), plane.s)
    controllable = lines["controllable: the end still reachable"]
    np.testing.assert_array_equal(controllable.get_ydata(), plane.sd_controllable)
    for name in ("velocity", "acceleration"):
        drawn = [label for label in lines if label.startswith(f"{name} limit alone")]
        assert len(drawn) == 1, lines.keys()
    ax = figure.axes[0]
    assert ax.get_xlabel() == "path position s [rad]"
    assert ax.get_ylabel() == "path velocity ds/dt [rad/s]"
    low, high = ax.get_ylim()
    assert low == 0.0 and high > np.max(plane.sd)  # the whole plan is in view
    legend = figure.legends[0]  # beside the axes, not on the data
    assert "TOPPRA's plan" in [text.get_text() for text in legend.get_texts()]


def test_a_limit_that_bounds_nothing_is_named_so(line_plane):
    figure = plot_phase_plane(line_plane)
    lines = _lines(figure)
    assert "acceleration limit alone: no bound on this path" in lines
    assert np.all(np.isnan(lines["acceleration limit alone: no bound on this path"].get_ydata()))


def test_it_draws_into_given_axes(line_plane):
    import matplotlib.pyplot as plt

    figure, (left, right) = plt.subplots(1, 2)
    assert plot_phase_plane(line_plane, ax=right) is figure
    assert not left.lines and right.lines
    assert right.get_legend() is not None
    plt.close(figure)


def test_anything_but_a_phase_plane_is_refused(line_plane):
    with pytest.raises(InvalidInputError, match="plane must be a PhasePlane"):
        plot_phase_plane(line_plane.sd)


def test_a_bound_far_above_the_plan_is_named_as_above_the_axes(line_plane):
    plane = line_plane
    far = dataclasses.replace(plane, bounds={**plane.bounds, "torque": 100.0 * plane.sd_max})
    figure = plot_phase_plane(far)
    assert "torque limit alone (above the axes)" in _lines(figure)
    assert figure.axes[0].get_ylim()[1] < np.min(far.bounds["torque"])
