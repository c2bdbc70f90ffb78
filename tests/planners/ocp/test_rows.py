"""Tests of planners.ocp.rows."""

from __future__ import annotations

import numpy as np
from ocp_support import exact_motion, nlp_rows, youbot_nlp

from optraj.planners.ocp.transcription import (
    torque_linearization,
    torque_parameter_count,
)


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
    robot, compiled = youbot_nlp(torque_nodes=nodes, torque_rows="linear")
    layout = compiled.layout
    margin = 0.05
    rng = np.random.default_rng(3)
    w = exact_motion(compiled, rng)
    w[layout.x_start : layout.u_start] = rng.uniform(-0.8, 0.8, layout.u_start - layout.x_start)
    block = torque_linearization(compiled, w, margin)
    assert block.size == torque_parameter_count(compiled.structure) == len(nodes) * (5 + 3 * 25)
    p = compiled.parameters.vector(torque=block)
    np.testing.assert_array_equal(compiled.parameters.value(p, "torque"), block)

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


def test_bernstein_rows_bound_velocity_and_position_between_nodes():
    # The rows are Bernstein coefficients: the polynomial stays within their hull.
    _, compiled = youbot_nlp()
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    rng = np.random.default_rng(1)
    for _ in range(5):
        w = exact_motion(compiled, rng)
        h, states, jerks = layout.split(w)
        n = layout.n
        speed_rows = nlp_rows(compiled, w, "velocity between nodes").reshape(layout.K, n)
        position_rows = nlp_rows(compiled, w, "position between nodes").reshape(layout.K, 2, n)
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
