"""Tests of planners.ocp.transcription: the NLP rows against independent computations."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from conftest import get_robot

from optraj.planners.ocp.transcription import (
    FrozenOptions,
    Structure,
    compile_nlp,
    freeze_options,
    parameter_vector,
    structure_limits,
    thaw_options,
)
from optraj.robots import SymbolicModel


def _compiled(intervals=(4, 3), **fields):
    robot = get_robot("youbot")
    structure = Structure(
        robot=robot.name,
        limits=structure_limits(robot.limits),
        tool_frame=robot.tool_frame,
        intervals=intervals,
        free=(True, False),
        **fields,
    )
    return robot, compile_nlp(structure, SymbolicModel(robot))


def _rows(compiled, w, name):
    g = ca.Function("g", [compiled.w, compiled.p], [compiled.g])(w, parameter_vector())
    g = np.asarray(g).reshape(-1)
    return np.concatenate([g[a:b] for group, a, b in compiled.groups if group == name])


def _exact_motion(compiled, rng):
    """A decision vector whose nodes follow the exact triple integrator (numpy, not CasADi)."""
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    n = layout.n
    w = np.zeros(layout.size)
    h = rng.uniform(0.02, 0.08, layout.K)
    w[: layout.K] = h
    q, v, a = mid + 0.2 * half * rng.uniform(-1, 1, n), 0.1 * vel * rng.uniform(-1, 1, n), 0 * vel
    for k in range(layout.K + 1):
        w[layout.x_index(k, 0)] = (q - mid) / half
        w[layout.x_index(k, 1)] = v / vel
        w[layout.x_index(k, 2)] = a / acc
        if k == layout.K:
            break
        u = jerk * rng.uniform(-0.5, 0.5, n)
        w[layout.u_index(k)] = u / jerk
        q, v, a = (
            q + h[k] * v + h[k] ** 2 / 2 * a + h[k] ** 3 / 6 * u,
            v + h[k] * a + h[k] ** 2 / 2 * u,
            a + h[k] * u,
        )
    return w


def test_exact_integration_satisfies_the_dynamics_rows():
    _, compiled = _compiled()
    w = _exact_motion(compiled, np.random.default_rng(0))
    np.testing.assert_allclose(_rows(compiled, w, "dynamics"), 0.0, atol=1e-12)
    w[compiled.layout.u_index(2)] += 0.1  # another jerk on interval 2 breaks its step
    assert np.abs(_rows(compiled, w, "dynamics")).max() > 1e-3


def test_rows_are_labelled_with_their_joint_part_and_place():
    _, compiled = _compiled()
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
    _, compiled = _compiled(intervals=(3, 2), torque_nodes=(1, 4))
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
    _, compiled = _compiled(options=options)
    passed = {}
    monkeypatch.setattr(
        "optraj.planners.ocp.transcription._nlpsol",
        lambda nlp, given: passed.update(given) or "solver",
    )
    assert compiled.warm() == "solver"
    assert passed["ipopt.mu_init"] == pytest.approx(barrier, rel=1e-12)
    assert passed["ipopt.warm_start_init_point"] == "yes"
