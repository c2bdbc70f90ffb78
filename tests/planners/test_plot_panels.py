"""Tests of planners.plot_panels: labelled plans, checked inputs, samples, strike bands."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import planners
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners import plot_panels, plot_style

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


def _still(dof=2, phases=()):
    return planners.Trajectory(
        [0.0, 1.0], np.zeros((1, 2, dof)), phases=phases, metadata={"planner": "still"}
    )


def test_named_labels_one_plan_by_its_planner_and_keeps_a_mapping():
    assert list(plot_panels.named(_still())) == ["still"]
    assert list(plot_panels.named({"a": _still(), "b": _still()})) == ["a", "b"]
    for bad in ({}, [_still()], {"a": 1}):
        with pytest.raises(InvalidInputError, match="trajectories must be"):
            plot_panels.named(bad)


def test_inputs_are_checked():
    with pytest.raises(InvalidInputError, match="trajectory 'a' has 2 joints, the limits 3"):
        plot_panels.check_dof({"a": _still()}, 3, "the limits")
    with pytest.raises(InvalidInputError, match="at least one"):
        plot_panels.quantities_of([], plot_panels.QUANTITIES)
    with pytest.raises(UnknownNameError, match="snap"):
        plot_panels.quantities_of(["snap"], plot_panels.QUANTITIES)
    assert plot_panels.quantities_of(("jerk", "position"), plot_panels.QUANTITIES) == [
        "jerk",
        "position",
    ]


def test_samples_hold_every_breakpoint_and_strikes_are_shaded_per_plan():
    plan = _still(phases=[planners.Phase("strike", 0.25, 0.5)])
    sample = plot_panels.samples_of({"a": plan}, 10.0)["a"]
    assert sample.t[0] == 0.0 and sample.t[-1] == 1.0
    plt = plot_style.pyplot()
    figure, ax = plt.subplots()
    styles = plot_style.line_styles(["none", "a"])
    plot_panels.shade_strikes(ax, {"none": _still(), "a": plan}, styles)
    assert len(ax.patches) == 2  # band and bar of "a" only, in the first bar row
    assert all(
        matplotlib.colors.same_color(p.get_facecolor()[:3], styles["a"].color) for p in ax.patches
    )
    assert ax.patches[1].get_y() == pytest.approx(0.0)
    plt.close(figure)
