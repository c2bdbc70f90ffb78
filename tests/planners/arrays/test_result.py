"""Tests of planners.arrays.result: the samples' fields, synonyms and shapes."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import time_base
from optraj.planners.arrays.result import SampledProfile, sample_fields
from optraj.planners.trajectory import Trajectory


def _line(n):
    """q = 1 + 2 t on every joint over [0, 4]."""
    coefficients = np.zeros((1, 2, n))
    coefficients[0, 0], coefficients[0, 1] = 1.0, 2.0
    return Trajectory([0.0, 4.0], coefficients)


def test_sample_fields_evaluate_the_trajectory_at_the_times():
    base = time_base(5)
    t, q, qd, qdd = sample_fields(_line(3), base, scalar=False)
    np.testing.assert_array_equal(t, base.times)
    np.testing.assert_allclose(q, np.repeat((1.0 + 2.0 * base.times)[:, None], 3, axis=1))
    np.testing.assert_allclose(qd, 2.0)
    np.testing.assert_allclose(qdd, 0.0)
    assert q.shape == qd.shape == qdd.shape == (5, 3)


def test_scalar_fields_are_one_dimensional():
    _, q, qd, qdd = sample_fields(_line(1), time_base(5), scalar=True)
    assert q.shape == qd.shape == qdd.shape == (5,)
    np.testing.assert_allclose(q, [1.0, 3.0, 5.0, 7.0, 9.0])


def test_the_toolbox_names_are_synonyms_and_arrays_are_read_only():
    traj = _line(2)
    base = time_base([0.0, 2.0, 4.0])
    profile = SampledProfile("jtraj", *sample_fields(traj, base, scalar=False), True, traj)
    assert profile.s is profile.q and profile.sd is profile.qd and profile.sdd is profile.qdd
    assert len(profile) == 3
    assert profile.naxes == 2
    assert "3 samples x 2 axes" in repr(profile) and "[0, 4] s" in repr(profile)
    with pytest.raises(ValueError, match="read-only"):
        profile.q[0, 0] = 5.0
    scalar = SampledProfile("quintic", *sample_fields(_line(1), base, scalar=True), False, traj)
    assert scalar.naxes == 1
    assert "steps" in repr(scalar)


def test_samples_that_overflow_are_refused():
    coefficients = np.zeros((1, 6, 1))
    coefficients[0, 5, 0] = 1e306  # finite coefficients, q(4) = 1e306 * 4^5 overflows
    with pytest.raises(InvalidInputError, match="overflow double precision"):
        sample_fields(Trajectory([0.0, 4.0], coefficients), time_base(5), scalar=True)
