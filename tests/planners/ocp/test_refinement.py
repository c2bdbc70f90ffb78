"""Tests of planners.ocp.refinement."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import (
    InvalidInputError,
)
from optraj.planners import Trajectory
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
    WarmStart,
    strike_caps,
)
from optraj.planners.ocp.options import SHRINK_EXTRA
from optraj.planners.ocp.refinement import (
    constraint_duals,
    position_excess,
    shrunk,
    tightened,
)
from optraj.planners.ocp.transcription import compile_nlp
from optraj.robots import SymbolicModel


def test_strike_caps_bound_the_strike_nodes_only():
    assert strike_caps(0.9, 0.999) == (0.999, 0.999)
    velocity, acceleration = strike_caps(0.01, 0.999)
    assert velocity == pytest.approx(3.0 * 0.01) and acceleration == pytest.approx(10.0 * 1e-4)
    planner = OptimalControl("time")
    keep = 1.0 - planner.margin
    built = planner.build(problems.sawyer_pool_shot(0.03))
    layout, ratio = built.compiled.layout, built.contact.ratio
    assert 0.0 < ratio < 0.05  # 0.03 m/s needs a few percent of the velocity limits
    first = built.grids[0].intervals  # the approach's last node starts the strike
    last = first + built.grids[1].intervals
    for node in (first - 1, *range(first, last + 1), last + 1):
        inside = first <= node <= last
        for block, cap in ((1, 3.0 * ratio), (2, 10.0 * ratio**2)):
            index = layout.x_index(node, block)
            expected = cap if inside else keep
            assert built.ubx[index] == pytest.approx(np.full(7, expected), rel=1e-12)
            assert built.lbx[index] == pytest.approx(np.full(7, -expected), rel=1e-12)


@pytest.mark.parametrize(
    ("ratio", "keep", "name"),
    [(-0.1, 1.0, "ratio"), (float("nan"), 1.0, "ratio"), (0.5, 0.0, "keep"), (0.5, 1.5, "keep")],
)
def test_strike_caps_name_bad_input(ratio, keep, name):
    with pytest.raises(InvalidInputError) as info:
        strike_caps(ratio, keep)
    assert info.value.name == name


def test_shrunk_moves_both_node_bounds_of_a_piece_in_by_twice_its_excess():
    limits = get_robot("paddle4").limits
    excess = np.zeros((2, 2, limits.n))  # 2 pieces; (below lower, above upper) per joint
    excess[1, 1, 2] = 0.01  # piece 1 passes joint 2's upper limit
    moved = shrunk(None, excess, limits)
    expected = np.zeros((3, 2, limits.n))
    expected[1:, 1, 2] = 0.02 + SHRINK_EXTRA
    np.testing.assert_allclose(moved, expected)
    again = shrunk(moved, excess, limits)  # still passing: moved in further
    np.testing.assert_allclose(again[1:, 1, 2], 2 * (0.02 + SHRINK_EXTRA))
    huge = shrunk(None, excess * 1e3, limits)  # capped at a quarter of the range
    np.testing.assert_allclose(huge[1:, 1, 2], 0.25 * (limits.upper[2] - limits.lower[2]))


def test_position_excess_finds_the_extremes_between_the_knots():
    rng = np.random.default_rng(11)
    limits = get_robot("paddle4").limits
    middle = 0.5 * (limits.lower + limits.upper)
    half = 0.5 * (limits.upper - limits.lower)
    knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.05, 0.3, 3))])
    outcomes = []
    for _ in range(60):
        # Three cubic pieces through random points inside the range at random velocities.
        points = middle + half * rng.uniform(-0.98, 0.98, (4, limits.n))
        slopes = rng.uniform(-1.0, 1.0, (4, limits.n)) * 2.0 * half / 0.1
        traj = Trajectory.from_hermite(knots, points, slopes)
        dense = traj.sample(np.linspace(0.0, knots[-1], 20001)).q
        inside = bool(np.all(dense >= limits.lower) and np.all(dense <= limits.upper))
        assert (not position_excess(traj, limits).any()) == inside
        outcomes.append(inside)
    assert 10 <= sum(outcomes) <= 50  # both verdicts are exercised


def test_tightened_raises_both_ends_of_an_interval_by_its_excess():
    margins = np.full((3, 2), 0.01)
    ratio = np.zeros((9, 2))  # 2 intervals, 4 points each, and the last node
    ratio[2, 1] = -1.02  # inside interval 0, joint 1: 0.025 over 1 - 0.01 / 2
    ratio[8, 0] = 0.99  # last node, joint 0: within 1 - 0.005
    raised = tightened(margins, ratio)
    np.testing.assert_allclose(raised[:, 0], 0.01)
    np.testing.assert_allclose(raised[:, 1], [0.01 + 0.025 + 0.005] * 2 + [0.01])
    ratio[8, 0] = 5.0
    assert tightened(margins, ratio).max() == 0.5  # capped


def test_constraint_duals_carry_over_where_only_the_torque_rows_differ():
    robot = get_robot("youbot")
    problem = problems.PointToPoint(robot, robot.home, robot.home + 0.3)
    saved = OptimalControl("time", torque=False).plan(problem).metadata["warm_start"]
    n, model = robot.dof, SymbolicModel(robot)
    rng = np.random.default_rng(5)

    def warm(structure):
        compiled = compile_nlp(structure, model)
        lam_g = rng.standard_normal(compiled.lbg.size)
        return compiled, WarmStart(structure, saved.w, saved.lam_x, lam_g)

    base = saved.lam_g.size
    rnea, start = warm(dataclasses.replace(saved.structure, torque_nodes=(1, 2)))
    linear, _ = warm(
        dataclasses.replace(saved.structure, torque_nodes=(0, 2, 3), torque_rows="linear")
    )
    lam = constraint_duals(start, linear)
    np.testing.assert_array_equal(lam[:base], start.lam_g[:base])
    np.testing.assert_array_equal(lam[base : base + n], 0.0)  # node 0: new rows start at zero
    np.testing.assert_array_equal(lam[base + n : base + 2 * n], start.lam_g[base + n :])  # node 2
    np.testing.assert_array_equal(lam[base + 2 * n :], 0.0)
    np.testing.assert_array_equal(constraint_duals(start, rnea), start.lam_g)
    other_grid = compile_nlp(
        dataclasses.replace(
            saved.structure, intervals=tuple(i + 1 for i in saved.structure.intervals)
        ),
        model,
    )
    assert constraint_duals(start, other_grid) is None
