"""Tests of planners.profiles.peaks: closed forms, vectorised roots, bounds and ranges.

The reference is the root-by-root computation: for each joint alone, ``np.roots`` of the
derivative, its real roots inside (0, T) and both ends as candidates.
"""

from __future__ import annotations

import numpy as np
import pytest

from optraj.planners.profiles.peaks import (
    REST_PEAKS,
    peak_of,
    polynomial_peaks,
    rest_to_rest_peaks,
)
from optraj.planners.profiles.polynomial_coefficients import (
    cubic_coefficients,
    quintic_coefficients,
)

poly = np.polynomial.polynomial


def _reference_extremes(column: np.ndarray, duration: float) -> tuple[float, float]:
    """Lowest and highest value on [0, T] of one polynomial (ascending powers), root by root."""
    candidates = [0.0, duration]
    slope = poly.polyder(column)
    if slope.size and np.any(slope != 0.0):
        roots = np.roots(slope[::-1])
        candidates += [r.real for r in roots if abs(r.imag) < 1e-9 and 0.0 < r.real < duration]
    values = poly.polyval(np.array(candidates), column)
    return float(values.min()), float(values.max())


def _reference_peaks(coefficients: np.ndarray, duration: float) -> dict[str, np.ndarray]:
    out: dict[str, list[float]] = {key: [] for key in ("position_min", "position_max")}
    for quantity in ("velocity", "acceleration", "jerk"):
        out[quantity] = []
    for column in coefficients.T:
        low, high = _reference_extremes(column, duration)
        out["position_min"].append(low)
        out["position_max"].append(high)
        for order, quantity in enumerate(("velocity", "acceleration", "jerk"), start=1):
            low, high = _reference_extremes(poly.polyder(column, order), duration)
            out[quantity].append(max(high, -low))
    return {key: np.array(values) for key, values in out.items()}


def _assert_same_peaks(found, expected, rtol=1e-12):
    for key, values in expected.items():
        scale = np.maximum(1.0, np.abs(values))
        np.testing.assert_array_less(np.abs(found[key] - values), rtol * scale, err_msg=key)


@pytest.mark.parametrize("degree", [3, 5])
def test_rest_to_rest_closed_forms_equal_the_root_based_peaks(degree):
    rng = np.random.default_rng(35)
    for _ in range(200):
        n = int(rng.integers(1, 8))
        q0, q1 = rng.uniform(-3.0, 3.0, (2, n))
        duration = float(rng.uniform(0.05, 20.0))
        if degree == 3:
            coefficients = cubic_coefficients(q0, q1, duration)
        else:
            coefficients = quintic_coefficients(q0, q1, duration)
        closed = rest_to_rest_peaks(q0, q1, duration, degree)
        _assert_same_peaks(closed, _reference_peaks(coefficients, duration))
        _assert_same_peaks(closed, polynomial_peaks(coefficients, duration))


def test_rest_peak_constants_are_those_of_the_shapes_on_a_fine_grid():
    x = np.linspace(0.0, 1.0, 200_001)
    shapes = {3: [0, 0, 3, -2], 5: [0, 0, 0, 10, -15, 6]}
    for degree, shape in shapes.items():
        sampled = [np.abs(poly.polyval(x, poly.polyder(shape, k))).max() for k in (1, 2, 3)]
        np.testing.assert_allclose(REST_PEAKS[degree], sampled, rtol=1e-9)


@pytest.mark.parametrize("degree", [3, 5])
def test_general_peaks_equal_the_root_based_peaks_with_moving_ends(degree):
    rng = np.random.default_rng(36)
    for _ in range(300):
        n = int(rng.integers(1, 8))
        q0, q1, v0, v1, a0, a1 = rng.uniform(-2.0, 2.0, (6, n))
        duration = float(rng.uniform(0.05, 5.0))
        if degree == 3:
            coefficients = cubic_coefficients(q0, q1, duration, v0, v1)
        else:
            with_accelerations = rng.random() < 0.5
            coefficients = quintic_coefficients(
                q0, q1, duration, v0, v1, *((a0, a1) if with_accelerations else (0.0, 0.0))
            )
        peaks = polynomial_peaks(coefficients, duration)
        _assert_same_peaks(peaks, _reference_peaks(coefficients, duration), rtol=1e-11)
        for quantity in ("velocity", "acceleration", "jerk"):
            np.testing.assert_array_equal(
                peak_of(quantity, coefficients, duration), peaks[quantity]
            )


def test_degenerate_derivatives_lose_no_extreme():
    """Multiple, nearly multiple and vanishing leading roots, and columns that are all zero."""
    rng = np.random.default_rng(37)
    x = np.linspace(0.0, 1.0, 100_001)
    for _ in range(300):
        roots = rng.uniform(-0.5, 1.5, 3)
        kind = int(rng.integers(0, 5))
        if kind == 0:
            roots[:] = roots[0]  # a triple root of the acceleration
        elif kind == 1:
            roots[1] = roots[0]
        elif kind == 2:
            roots[1] = roots[0] + 1e-9
        acceleration = np.poly(roots)[::-1] * rng.uniform(0.1, 10.0)
        if kind == 3:
            acceleration[3] *= 1e-9  # nearly quadratic
        elif kind == 4:
            acceleration[3] = 0.0
        velocity = np.concatenate([[rng.uniform(-1, 1)], acceleration / np.arange(1.0, 5.0)])
        position = np.concatenate([[rng.uniform(-1, 1)], velocity / np.arange(1.0, 6.0)])
        coefficients = np.stack([position, -position, np.zeros(6)], axis=1)
        peaks = polynomial_peaks(coefficients, 1.0)
        sampled = np.abs(poly.polyval(x, velocity)).max()
        # the fine grid is within 1e-9 of the true peak: the peak found is that peak
        assert peaks["velocity"][0] == pytest.approx(sampled, rel=1e-9)
        assert peaks["velocity"][1] == peaks["velocity"][0]
        assert peaks["velocity"][2] == 0.0 and peaks["position_max"][2] == 0.0
