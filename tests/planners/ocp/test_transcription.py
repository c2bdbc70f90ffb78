"""Tests of planners.ocp.transcription: the NLP rows against independent computations."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.ocp.transcription import (
    PARAMETERS,
    FrozenOptions,
    Layout,
    Structure,
    compile_nlp,
    deadline,
    freeze_options,
    parameter_vector,
    structure_limits,
    thaw_options,
    time_left,
    torque_linearization,
    torque_parameter_count,
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


def test_bernstein_rows_bound_velocity_and_position_between_nodes():
    # The rows are Bernstein coefficients: the polynomial stays within their hull.
    _, compiled = _compiled()
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    rng = np.random.default_rng(1)
    for _ in range(5):
        w = _exact_motion(compiled, rng)
        h, states, jerks = layout.split(w)
        n = layout.n
        speed_rows = _rows(compiled, w, "velocity between nodes").reshape(layout.K, n)
        position_rows = _rows(compiled, w, "position between nodes").reshape(layout.K, 2, n)
        for k in range(layout.K):
            tau = np.linspace(0.0, h[k], 50)[:, None]
            q0 = mid + half * states[k, :n]
            v0, a0 = vel * states[k, n : 2 * n], acc * states[k, 2 * n :]
            u = jerk * jerks[k]
            v = v0 + a0 * tau + u * tau**2 / 2
            q = q0 + v0 * tau + a0 * tau**2 / 2 + u * tau**3 / 6
            v_hull = np.stack([v[0], vel * speed_rows[k], v[-1]])
            assert np.all(v <= v_hull.max(axis=0) + 1e-12)
            assert np.all(v >= v_hull.min(axis=0) - 1e-12)
            q_hull = np.stack([q[0], *(mid + half * position_rows[k]), q[-1]])
            assert np.all(q <= q_hull.max(axis=0) + 1e-12)
            assert np.all(q >= q_hull.min(axis=0) - 1e-12)


def test_layout_splits_what_it_indexes():
    layout = Layout(3, (2, 4))
    w = np.arange(layout.size, dtype=float)
    h, states, jerks = layout.split(w)
    assert h.shape == (6,) and states.shape == (7, 9) and jerks.shape == (6, 3)
    np.testing.assert_array_equal(states[5, 3:6], w[layout.x_index(5, 1)])
    np.testing.assert_array_equal(jerks[4], w[layout.u_index(4)])
    np.testing.assert_array_equal(layout.first_node, [0, 2, 6])


def test_parameter_vector_names_what_is_wrong():
    assert parameter_vector().size == sum(size for _, size in PARAMETERS)
    with pytest.raises(InvalidInputError, match="speed"):
        parameter_vector(speed=[1.0, 2.0])
    with pytest.raises(UnknownNameError, match="unknown NLP parameter 'velocity'"):
        parameter_vector(velocity=1.0)
    for bad in (True, "1.0", np.nan):  # no bool, string or NaN posing as a speed
        with pytest.raises(InvalidInputError, match="speed"):
            parameter_vector(speed=bad)


def test_rows_are_labelled_with_their_joint_part_and_place():
    _, compiled = _compiled()
    n, layout = compiled.layout.n, compiled.layout
    # Interval k's dynamics rows: position, velocity and acceleration steps of every joint.
    rows = np.concatenate([np.arange(a, b) for name, a, b in compiled.groups if name == "dynamics"])
    assert compiled.row_joint[rows].tolist() == list(range(n)) * 3 * layout.K
    assert compiled.row_part[rows].tolist() == ([0] * n + [1] * n + [2] * n) * layout.K
    assert compiled.row_at[rows].tolist() == np.repeat(np.arange(layout.K), 3 * n).tolist()
    assert compiled.row_joint.size == compiled.lbg.size == compiled.row_at.size


def test_a_solve_past_its_deadline_is_stopped_by_the_iteration_callback():
    _, compiled = _compiled(options=(("ipopt.max_iter", 3), ("ipopt.print_level", 0)))
    rng = np.random.default_rng(3)
    w = _exact_motion(compiled, rng)
    args = {"x0": w, "p": parameter_vector(), "lbg": compiled.lbg, "ubg": compiled.ubg}
    assert time_left() == np.inf
    with deadline(-1.0):  # already past
        assert time_left() < 0.0
        compiled.solver(**args)
    stats = compiled.solver.stats()
    assert stats["return_status"] == "User_Requested_Stop" and stats["iter_count"] == 0
    with deadline(3600.0), deadline(7200.0):  # the nearer deadline holds
        assert 3500.0 < time_left() <= 3600.0
        compiled.solver(**args)
    assert compiled.solver.stats()["return_status"] != "User_Requested_Stop"
    assert time_left() == np.inf


def _node_torques(robot, compiled, w, nodes):
    """Pinocchio's inverse dynamics at the nodes of ``w``, over the effort limits."""
    mid, half, vel, acc, _ = compiled.scale
    _, states, _ = compiled.layout.split(w)
    n = compiled.layout.n
    x = states[list(nodes)]
    tau = robot.inverse_dynamics(mid + half * x[:, :n], vel * x[:, n : 2 * n], acc * x[:, 2 * n :])
    return tau / robot.limits.effort


def test_linear_torque_rows_are_the_rnea_to_first_order():
    nodes = (0, 2, 5, 7)
    robot, compiled = _compiled(torque_nodes=nodes, torque_rows="linear")
    layout = compiled.layout
    margin = 0.05
    rng = np.random.default_rng(3)
    w = _exact_motion(compiled, rng)
    w[layout.x_start : layout.u_start] = rng.uniform(-0.8, 0.8, layout.u_start - layout.x_start)
    block = torque_linearization(compiled, w, margin)
    assert block.size == torque_parameter_count(compiled.structure) == len(nodes) * (5 + 3 * 25)
    p = np.concatenate([parameter_vector(), block])

    def rows(x):
        g = np.asarray(compiled.constraint_values(x, p)).reshape(-1)
        return np.concatenate([g[a:b] for name, a, b in compiled.groups if name == "torque"])

    exact = _node_torques(robot, compiled, w, nodes) / (1.0 - margin)
    np.testing.assert_allclose(rows(w), exact.reshape(-1), atol=1e-12)
    step = np.zeros_like(w)
    step[layout.x_start : layout.u_start] = rng.standard_normal(layout.u_start - layout.x_start)
    for eps in (1e-3, 1e-4):  # the error shrinks with the square of the step: the slope is right
        moved = _node_torques(robot, compiled, w + eps * step, nodes) / (1.0 - margin)
        error = np.abs(rows(w + eps * step) - moved.reshape(-1)).max()
        change = np.abs(moved - exact).max()
        assert error < 1e-3 * change, (eps, error, change)


def test_unknown_torque_rows_are_named():
    with pytest.raises(UnknownNameError, match="rnea"):
        _compiled(torque_nodes=(1,), torque_rows="quadratic")


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
