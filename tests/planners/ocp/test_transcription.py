"""Tests of planners.ocp.transcription: the NLP rows against independent computations."""

from __future__ import annotations

import numpy as np
import pytest
from ocp_support import exact_motion, nlp_rows, youbot_nlp

from optraj.planners.ocp.transcription import (
    FrozenOptions,
    freeze_options,
    thaw_options,
)


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
