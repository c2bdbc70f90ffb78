"""Tests of planners.arrays.stacking: one-joint trajectories stacked, re-expanded exactly."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.arrays.stacking import shifted_coefficients, stack_joints
from optraj.planners.trajectory import Trajectory


def test_shifted_coefficients_give_the_same_polynomial():
    rng = np.random.default_rng(0)
    c = rng.normal(size=(4, 6, 2))
    shift = rng.uniform(-1.0, 1.0, 4)
    out = shifted_coefficients(c, shift)
    tau = np.linspace(-0.5, 0.5, 7)
    for k in range(4):
        for j in range(2):
            want = np.polyval(c[k, ::-1, j], tau + shift[k])
            np.testing.assert_allclose(np.polyval(out[k, ::-1, j], tau), want, rtol=1e-12)


def _random_one_joint(rng, duration):
    """A one-joint trajectory of random breakpoints, degree and coefficients over duration."""
    inner = np.sort(rng.uniform(0.0, duration, rng.integers(0, 4)))
    knots = np.concatenate([[0.0], inner, [duration]])
    degree = int(rng.integers(0, 6))
    return Trajectory(knots, rng.normal(size=(knots.size - 1, degree + 1, 1)))


def test_stacked_joints_sample_as_their_own_trajectories():
    rng = np.random.default_rng(36)
    for _ in range(30):
        duration = rng.uniform(0.5, 5.0)
        parts = [_random_one_joint(rng, duration) for _ in range(int(rng.integers(1, 6)))]
        stacked = stack_joints(parts, metadata={"planner": "test"})
        assert stacked.dof == len(parts) and stacked.metadata["planner"] == "test"
        # Right of every breakpoint of every part, and between them.
        t = np.concatenate([np.linspace(0.0, duration, 101), *(p.breakpoints for p in parts)])
        sample = stacked.sample(t)
        for j, part in enumerate(parts):
            own = part.sample(t)
            np.testing.assert_allclose(sample.q[:, j], own.q[:, 0], rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(sample.qd[:, j], own.qd[:, 0], rtol=1e-9, atol=1e-9)


def test_breakpoints_within_round_off_merge():
    # (K, degree + 1, 1): q = t then 2 - t; q = 2 t then 2.
    one = Trajectory([0.0, 1.0, 2.0], [[[0.0], [1.0]], [[1.0], [-1.0]]])
    other = Trajectory([0.0, 1.0 + 1e-15, 2.0], [[[0.0], [2.0]], [[2.0], [0.0]]])
    stacked = stack_joints([one, other])
    np.testing.assert_array_equal(stacked.breakpoints, [0.0, 1.0, 2.0])
    np.testing.assert_allclose(stacked.sample(1.5).q, [0.5, 2.0], atol=1e-12)


def test_bad_stacks_are_refused():
    with pytest.raises(InvalidInputError, match="one or more one-joint"):
        stack_joints([])
    with pytest.raises(InvalidInputError, match="one or more one-joint"):
        stack_joints([Trajectory.constant([0.0, 1.0], 1.0)])
    with pytest.raises(InvalidInputError, match="every joint must last 1, joint 1 lasts 2"):
        stack_joints([Trajectory.constant([0.0], 1.0), Trajectory.constant([0.0], 2.0)])
