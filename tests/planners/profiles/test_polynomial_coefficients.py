"""Tests of planners.profiles.polynomial_coefficients: the end states are met."""

from __future__ import annotations

import numpy as np

from optraj.planners.profiles.polynomial_coefficients import (
    cubic_coefficients,
    quintic_coefficients,
)


def test_boundary_conditions_met_for_random_data():
    rng = np.random.default_rng(5)
    for _ in range(200):
        q0, q1, v0, v1, a0, a1 = rng.uniform(-2, 2, size=(6, 4))
        T = rng.uniform(0.2, 3.0)
        for coeffs, states in (
            (quintic_coefficients(q0, q1, T, v0, v1, a0, a1), (q0, v0, a0, q1, v1, a1)),
            (cubic_coefficients(q0, q1, T, v0, v1), (q0, v0, None, q1, v1, None)),
        ):
            poly = np.polynomial.polynomial
            for t, (q, v, a) in ((0.0, states[:3]), (T, states[3:])):
                np.testing.assert_allclose(poly.polyval(t, coeffs), q, atol=1e-10)
                np.testing.assert_allclose(poly.polyval(t, poly.polyder(coeffs)), v, atol=1e-10)
                if a is not None:
                    np.testing.assert_allclose(
                        poly.polyval(t, poly.polyder(coeffs, 2)), a, atol=1e-9
                    )


def test_scalar_end_rates_broadcast_over_the_joints():
    q0, q1 = np.array([0.0, 1.0]), np.array([1.0, -1.0])
    np.testing.assert_array_equal(
        quintic_coefficients(q0, q1, 2.0, 0.5, 0.0, 0.0, 1.0),
        quintic_coefficients(q0, q1, 2.0, np.full(2, 0.5), np.zeros(2), np.zeros(2), np.ones(2)),
    )
    np.testing.assert_array_equal(
        cubic_coefficients(q0, q1, 2.0, 0.5), cubic_coefficients(q0, q1, 2.0, np.full(2, 0.5))
    )
