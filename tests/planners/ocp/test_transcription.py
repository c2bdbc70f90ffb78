"""Tests of planners.ocp.transcription: the NLP rows against independent computations."""

from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np
import pytest
from conftest import get_robot
from ocp_support import exact_motion, nlp_rows, youbot_nlp

from optraj.planners.ocp.transcription import (
    FrozenOptions,
    Structure,
    compile_nlp,
    freeze_options,
    structure_limits,
    thaw_options,
)
from optraj.robots import SymbolicModel


def test_exact_integration_satisfies_the_dynamics_rows():
    _, compiled = youbot_nlp()
    w = exact_motion(compiled, np.random.default_rng(0))
    np.testing.assert_allclose(nlp_rows(compiled, w, "dynamics"), 0.0, atol=1e-12)
    w[compiled.layout.u_index(2)] += 0.1  # another jerk on interval 2 breaks its step
    assert np.abs(nlp_rows(compiled, w, "dynamics")).max() > 1e-3


def test_rows_are_labelled_with_their_joint_part_and_place():
    _, compiled = youbot_nlp()
    n, layout = compiled.layout.n, compiled.layout
    # Interval k's dynamics rows: position, velocity and acceleration steps of every joint.
    rows = np.concatenate([np.arange(a, b) for name, a, b in compiled.groups if name == "dynamics"])
    assert compiled.row_joint[rows].tolist() == list(range(n)) * 3 * layout.K
    assert compiled.row_part[rows].tolist() == ([0] * n + [1] * n + [2] * n) * layout.K
    assert compiled.row_at[rows].tolist() == np.repeat(np.arange(layout.K), 3 * n).tolist()
    assert compiled.row_joint.size == compiled.lbg.size == compiled.row_at.size


def test_solver_options_frozen_for_a_structure_thaw_back_to_nested_mappings():
    options = {"ipopt.tol": 1e-6, "qpsol_options": {"b": [1, 2], "a": {"x": "y"}}}
    frozen = freeze_options(options)
    assert hash(frozen) == hash(
        freeze_options({"qpsol_options": {"a": {"x": "y"}, "b": [1, 2]}, "ipopt.tol": 1e-6})
    )
    assert isinstance(frozen, FrozenOptions)
    assert thaw_options(frozen) == {
        "ipopt.tol": 1e-6,
        "qpsol_options": {"a": {"x": "y"}, "b": (1, 2)},
    }


def test_group_order_gathers_every_row_of_each_group_once():
    _, compiled = youbot_nlp(intervals=(3, 2), torque_nodes=(1, 4))
    names, order, starts = compiled.group_order
    assert names == tuple(dict.fromkeys(name for name, _, _ in compiled.groups))
    assert sorted(order.tolist()) == list(range(compiled.lbg.size))
    ends = [*starts[1:].tolist(), order.size]
    for name, start, end in zip(names, starts.tolist(), ends, strict=True):
        rows = [r for group, a, b in compiled.groups if group == name for r in range(a, b)]
        assert order[start:end].tolist() == rows


@pytest.mark.parametrize(("tolerance", "barrier"), [(None, 1e-7), (1e-6, 1e-7), (1e-4, 1e-5)])
def test_a_warm_start_barrier_starts_at_a_tenth_of_the_tolerance(monkeypatch, tolerance, barrier):
    # A cold solve stops once its barrier problem is solved to 10 times the barrier parameter,
    # so a solution to tolerance t was found at a barrier of about t / 10.
    options = () if tolerance is None else (("ipopt.tol", tolerance),)
    _, compiled = youbot_nlp(options=options)
    passed = {}
    monkeypatch.setattr(
        "optraj.planners.ocp.transcription._nlpsol",
        lambda nlp, given: passed.update(given) or "solver",
    )
    assert compiled.warm() == "solver"
    assert passed["ipopt.mu_init"] == pytest.approx(barrier, rel=1e-12)
    assert passed["ipopt.warm_start_init_point"] == "yes"


def test_the_anchored_grid_term_is_zero_on_its_anchor_and_grows_off_it():
    # youbot_nlp's first phase is free, its second fixed: only free intervals are anchored.
    weights = (("anchor", 0.5), ("time", 1.0))
    _, anchored = youbot_nlp(weights=weights)
    _, plain = youbot_nlp(weights=(("time", 1.0),))
    K = anchored.layout.K
    w = exact_motion(anchored, np.random.default_rng(3))
    objective = ca.Function("f", [anchored.w, anchored.p], [anchored.f])
    time_only = ca.Function("f", [plain.w, plain.p], [plain.f])
    on = anchored.parameters.vector(time_scale=2.0, anchor=w[:K])
    expected = float(time_only(w, plain.parameters.vector(time_scale=2.0)))
    assert float(objective(w, on)) == pytest.approx(expected, rel=1e-14)
    moved = w[:K] + np.array([0.01, -0.02, 0.03, 0.0, 0.05, 0.05, 0.05])
    off = anchored.parameters.vector(time_scale=2.0, anchor=moved)
    # 0.5 K sum over the free intervals of ((h - anchor) / time_scale)^2.
    free = anchored.layout.phase_of == 0
    extra = 0.5 * K * np.sum(((w[:K] - moved)[free] / 2.0) ** 2)
    assert float(objective(w, off)) == pytest.approx(expected + extra, rel=1e-12)


def test_the_symbolic_rnea_is_built_only_for_torque_rows_or_an_effort_term():
    robot = get_robot("youbot")
    structure = Structure(
        robot=robot.name,
        limits=structure_limits(robot.limits),
        tool_frame=robot.tool_frame,
        intervals=(4,),
        free=(True,),
    )
    model = SymbolicModel(robot)
    compile_nlp(structure, model)
    assert ("rnea", 0) not in model._cache
    compile_nlp(replace(structure, torque_nodes=(0, 2), torque_rows="linear"), model)
    assert ("rnea", 0) in model._cache
    model = SymbolicModel(robot)
    compile_nlp(replace(structure, weights=(("effort", 1.0), ("time", 1.0))), model)
    assert ("rnea", 0) in model._cache
