"""Tests of planners.ocp.solution."""

from __future__ import annotations

import re

import numpy as np
from ocp_support import paddle_move, sawyer_shots

from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)
from optraj.planners.ocp.solution import diagnosis, integrable


def test_a_failed_solve_names_its_most_violated_row_by_joint_and_place():
    move = paddle_move()
    built = OptimalControl().build(move)
    layout = built.compiled.layout
    w = built.x0.copy()
    jerk = w[layout.u_index(2)]  # a view: interval 2's scaled jerks
    joint = int(np.argmin(np.abs(jerk)))
    jerk[joint] += 0.05  # breaks interval 2's dynamics rows of that joint only
    text = diagnosis(built, w)
    name = move.limits.names[joint]
    pattern = rf"most violated: dynamics \(the \w+ step\) of {name} at interval 2 of the move phase"
    assert re.match(pattern, text), text


def test_a_sampled_guess_is_fitted_to_the_dynamics_rows():
    planner = OptimalControl("time")
    built = planner.build(next(sawyer_shots(1, speed=1.0)))
    layout = built.compiled.layout
    kept = [int(node) for node in layout.first_node]
    rng = np.random.default_rng(5)
    noisy = built.x0.copy()
    noisy[layout.x_start :] += 0.05 * rng.standard_normal(noisy.size - layout.x_start)
    fitted = integrable(noisy, layout, built.compiled.scale, kept)
    assert built.violations(noisy)["dynamics"] > 1e-2
    assert built.violations(fitted)["dynamics"] < 1e-9
    np.testing.assert_array_equal(fitted[: layout.K], noisy[: layout.K])  # interval lengths
    # The phase ends keep their sampled states more closely than the other nodes.
    moved = np.abs(layout.split(fitted)[1] - layout.split(noisy)[1]).max(axis=1)
    assert moved[kept].mean() < 0.5 * np.delete(moved, kept).mean()
    # A solution already meets the rows: the fit leaves it (up to the small jerk weight).
    solved = planner.solve(built).metadata["warm_start"].w
    again = integrable(solved, layout, built.compiled.scale, kept)
    assert np.abs(again - solved).max() < 1e-4
