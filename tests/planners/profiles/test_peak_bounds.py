"""Tests of planners.profiles.peak_bounds: bounds that bracket the exact peaks."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.planners.profiles.peak_bounds import position_range, rate_bounds
from optraj.planners.profiles.peaks import extremes, polynomial_peaks
from optraj.planners.profiles.polynomial_coefficients import (
    cubic_coefficients,
    quintic_coefficients,
)


@pytest.mark.parametrize("degree", [3, 5])
def test_rate_bounds_bracket_the_exact_peaks(degree):
    rng = np.random.default_rng(38)
    for _ in range(300):
        q0, q1, v0, v1, a0, a1 = rng.uniform(-2.0, 2.0, (6, 7))
        duration = float(rng.uniform(0.05, 5.0))
        if degree == 3:
            coefficients = cubic_coefficients(q0, q1, duration, v0, v1)
        else:
            coefficients = quintic_coefficients(q0, q1, duration, v0, v1, a0, a1)
        exact = polynomial_peaks(coefficients, duration)
        lower, upper = rate_bounds(coefficients, duration)
        for row, quantity in enumerate(("velocity", "acceleration", "jerk")):
            assert np.all(lower[row] <= exact[quantity]), quantity
            assert np.all(exact[quantity] <= upper[row]), quantity
            assert np.all(upper[row] - lower[row] <= 0.05 * exact[quantity] + 1e-12), quantity


def test_position_range_is_exact_wherever_the_box_may_be_left():
    rng = np.random.default_rng(39)
    for _ in range(300):
        q0, q1, v0, v1 = rng.uniform(-1.0, 1.0, (4, 7))
        duration = float(rng.uniform(0.2, 3.0))
        coefficients = quintic_coefficients(q0, q1, duration, v0, v1)
        low, high = extremes(coefficients, duration)
        box = rng.uniform(0.9, 1.3)
        lower, upper = np.full(7, -box), np.full(7, box)
        screened_low, screened_high = position_range(coefficients, duration, lower, upper, 1e-9)
        # the range never claims less than the truth, and the box test answers as exactly
        assert np.all(screened_low <= low + 1e-12) and np.all(screened_high >= high - 1e-12)
        np.testing.assert_array_equal(lower - screened_low > 1e-9, lower - low > 1e-9)
        np.testing.assert_array_equal(screened_high - upper > 1e-9, high - upper > 1e-9)
