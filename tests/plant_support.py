"""Shared helpers of the plant tests (tests/controllers/test_*plant*.py)."""

from __future__ import annotations

import numpy as np

ROBOTS = ("sawyer", "paddle4")  # paddle4's first joint is prismatic


def alternating_command(robot, fraction):
    """A joint velocity command at ``fraction`` of the limits with alternating signs."""
    signs = np.where(np.arange(robot.dof) % 2 == 0, 1.0, -1.0)
    return fraction * robot.limits.velocity * signs


def inertia_by_rnea(robot, q):
    """Joint-space inertia matrix from RNEA columns: M e_j = rnea(q, 0, e_j) - g(q)."""
    n = robot.dof
    zeros = np.zeros(n)
    gravity = robot.inverse_dynamics(q, zeros, zeros)
    return np.column_stack([robot.inverse_dynamics(q, zeros, e) - gravity for e in np.eye(n)])
