"""Tests of planners.ocp.task_rows.boundary_state."""

from __future__ import annotations

import numpy as np

from optraj.planners.ocp.structure import Layout
from optraj.planners.ocp.task_rows import FixedState
from optraj.problems.constraints import BoundaryState


def test_a_boundary_state_is_pinned_exactly_at_its_end_of_the_motion():
    q, qd = np.array([0.1, 0.2]), np.array([0.0, 0.5])
    start = FixedState.of(BoundaryState("start", q, qd, tolerance=1e-3), phases=3)
    end = FixedState.of(BoundaryState("end", None, np.zeros(2)), phases=3)
    assert (start.phase, start.at, start.tolerance) == (0, "start", 0.0)
    assert (end.phase, end.at, end.q) == (2, "end", None)
    np.testing.assert_array_equal(start.qdd, [0.0, 0.0])  # left open: at rest's zero
    first_node = np.array([0, 4, 6, 9])
    assert start.node(first_node) == 0 and end.node(first_node) == 9
    exact = start.exact()
    assert exact is not None and exact[0] is q
    assert end.exact() is None
    assert FixedState(1, "end", q, qd, qd, tolerance=0.1).exact() is None


def test_pinned_bounds_are_the_scaled_state_within_the_position_tolerance():
    layout = Layout(2, (2, 1))
    mid, half, vel, acc = np.array([0.0, 1.0]), np.array([2.0, 2.0]), np.ones(2), np.ones(2)
    lbx, ubx = -np.ones(layout.size), np.ones(layout.size)
    state = FixedState(0, "end", np.array([1.0, 1.0]), None, np.array([0.5, 0.0]), 0.2)
    state.pin(lbx, ubx, layout, (mid, half, vel, acc), layout.first_node)
    np.testing.assert_allclose(lbx[layout.x_index(2, 0)], [0.4, -0.1])
    np.testing.assert_allclose(ubx[layout.x_index(2, 0)], [0.6, 0.1])
    np.testing.assert_array_equal(lbx[layout.x_index(2, 1)], [-1.0, -1.0])  # velocity free
    np.testing.assert_array_equal(lbx[layout.x_index(2, 2)], [0.5, 0.0])
    np.testing.assert_array_equal(ubx[layout.x_index(2, 2)], [0.5, 0.0])
