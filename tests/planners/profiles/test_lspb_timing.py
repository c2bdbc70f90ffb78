"""Tests of planners.profiles.lspb_timing: LSPB closed forms and limit checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.profiles.lspb_timing import (
    MIN_BLEND,
    finite_array,
    limit_excess,
    lspb_fixed,
    lspb_fixed_blend,
    lspb_fixed_cruise,
    lspb_fixed_shortest,
    lspb_min_time,
    lspb_shortest_blend,
    unit_suffix,
)

# ------------------------------------------------------------------------ closed forms


def test_min_time_trapezoid_triangle_zero_and_sign():
    delta = np.array([2.0, -2.0, 0.1, 0.0, 0.5])
    vmax = np.array([1.0, 1.0, 1.0, 1.0, 1.0])
    amax = np.array([2.0, 2.0, 2.0, 2.0, 2.0])
    timing = lspb_min_time(delta, vmax, amax)
    # Trapezoid: tb = vmax / amax, T = |d| / vmax + vmax / amax.
    np.testing.assert_allclose(timing.blend_time[:2], [0.5, 0.5], rtol=0, atol=1e-12)
    np.testing.assert_allclose(timing.duration[:2], [2.5, 2.5], rtol=0, atol=1e-12)
    np.testing.assert_allclose(timing.velocity[:2], [1.0, -1.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(timing.acceleration[:2], [2.0, -2.0], rtol=0, atol=1e-12)
    # Triangle (|d| < vmax^2 / amax = 0.5): tb = sqrt(|d| / amax), T = 2 tb, v = amax tb.
    tb = math.sqrt(0.1 / 2.0)
    assert timing.blend_time[2] == pytest.approx(tb, abs=1e-12)
    assert timing.duration[2] == pytest.approx(2 * tb, abs=1e-12)
    assert timing.velocity[2] == pytest.approx(2.0 * tb, abs=1e-12)
    # No motion: all zero.
    assert timing.duration[3] == timing.blend_time[3] == timing.velocity[3] == 0.0
    assert timing.acceleration[3] == 0.0
    # On the boundary |d| = vmax^2 / amax both forms agree: tb = 0.5, T = 1.
    assert timing.blend_time[4] == pytest.approx(0.5, abs=1e-12)
    assert timing.duration[4] == pytest.approx(1.0, abs=1e-12)
    # Every timing covers its displacement: d = v (T - tb).
    np.testing.assert_allclose(
        timing.velocity * (timing.duration - timing.blend_time), delta, atol=1e-12
    )


def test_min_time_broadcasts_scalars():
    timing = lspb_min_time([1.0, 4.0], 2.0, 1.0)
    np.testing.assert_allclose(timing.duration, [2.0, 4.0], atol=1e-12)  # triangle, trapezoid


def test_shortest_blend_matches_craig_formula():
    rng = np.random.default_rng(11)
    for _ in range(200):
        a = rng.uniform(0.5, 30.0)
        d = rng.uniform(-3.0, 3.0)
        T = math.sqrt(4.0 * abs(d) / a) * rng.uniform(1.0, 4.0)
        timing = lspb_shortest_blend([d], [a], T)
        v = (a * T - math.sqrt(a * a * T * T - 4.0 * a * abs(d))) / 2.0  # Craig, sec. 7.3
        assert abs(timing.velocity[0]) == pytest.approx(v, rel=1e-9, abs=1e-12)
        assert timing.blend_time[0] == pytest.approx(v / a, rel=1e-9, abs=1e-12)
        assert abs(timing.acceleration[0]) == pytest.approx(a, rel=1e-12)
        assert timing.velocity[0] * (T - timing.blend_time[0]) == pytest.approx(d, abs=1e-12)


def test_fixed_blend_and_cruise_formulas():
    delta = np.array([1.5, -0.3, 0.0])
    timing = lspb_fixed_blend(delta, 2.0, 0.4)
    np.testing.assert_allclose(timing.velocity, delta / 1.6, atol=1e-12)
    np.testing.assert_allclose(timing.acceleration, delta / 1.6 / 0.4, atol=1e-12)
    np.testing.assert_array_equal(timing.blend_time, 0.4)
    timing = lspb_fixed_cruise(delta, 2.0, 0.5)
    np.testing.assert_allclose(timing.blend_time, 0.75, atol=1e-12)
    np.testing.assert_allclose(timing.velocity, 2 * delta / 2.5, atol=1e-12)


def test_fixed_dispatches_on_the_setting():
    delta = np.array([1.5, -0.3, 0.0])
    for setting, formula in (("blend_time", lspb_fixed_blend), ("cruise_time", lspb_fixed_cruise)):
        for got, expected in zip(
            lspb_fixed(delta, 2.0, setting, 0.4), formula(delta, 2.0, 0.4), strict=True
        ):
            np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("setting", ["blend_time", "cruise_time"])
def test_fixed_shortest_duration_sits_on_a_limit(setting):
    rng = np.random.default_rng(17)
    for _ in range(200):
        delta = rng.uniform(-2.0, 2.0, 4) * (rng.random(4) < 0.8)
        delta[0] = 0.5
        vmax, amax = rng.uniform(0.2, 5.0, 4), rng.uniform(0.5, 40.0, 4)
        tb = rng.uniform(0.05, 0.6)
        T = lspb_fixed_shortest(delta, vmax, amax, setting, tb)
        timing = lspb_fixed(delta, T, setting, tb)
        assert limit_excess(timing, vmax, amax) == []
        np.testing.assert_allclose(timing.velocity * (T - timing.blend_time), delta, atol=1e-12)
        # Shorter by a part in a million, some limit (or the blend's fit) breaks.
        floor = 2.0 * tb if setting == "blend_time" else tb / (1.0 - 2.0 * MIN_BLEND)
        if floor * (1 + 1e-6) < T:
            shorter = lspb_fixed(delta, T * (1 - 1e-6), setting, tb)
            assert limit_excess(shorter, vmax, amax)


def test_limit_excess_lists_every_excess_worst_first():
    timing = lspb_fixed_blend(np.array([1.0, -3.0, 0.1]), 2.0, 0.5)  # v = d / 1.5, a = v / 0.5
    found = limit_excess(timing, np.array([1.0, 1.0, 1.0]), np.array([1.0, 2.5, 1.0]))
    assert [(quantity, j) for quantity, j, _, _ in found] == [
        ("velocity", 1),
        ("acceleration", 1),
        ("acceleration", 0),
    ]
    assert found[0][2] == pytest.approx(2.0) and found[0][3] == 1.0
    assert limit_excess(timing, np.full(3, 2.0), np.full(3, 4.0)) == []


def test_units_and_arrays_for_messages_and_inputs():
    assert unit_suffix("rad", 1) == " rad/s"
    assert unit_suffix("m", 2) == " m/s^2"
    assert unit_suffix("", 2) == ""
    np.testing.assert_array_equal(finite_array([[1, 2], [3, 4]], "x"), [[1.0, 2.0], [3.0, 4.0]])
    with pytest.raises(InvalidInputError, match="x must be finite"):
        finite_array([1.0, math.inf], "x")


def test_bad_inputs_are_typed_errors():
    with pytest.raises(InvalidInputError, match="v_max must be > 0"):
        lspb_min_time([1.0], [0.0], [1.0])
    with pytest.raises(InvalidInputError, match="matching shapes"):
        lspb_min_time([1.0, 2.0], [1.0, 1.0, 1.0], 1.0)
    with pytest.raises(InfeasibleError, match="joint '0' at 4"):
        lspb_shortest_blend([1.0], [1.0], 1.0)


# issue 32, defect 6: numbers are numbers (np.array(..., dtype=float) took "1" and True)
def test_text_and_bools_are_not_numbers():
    with pytest.raises(InvalidInputError, match="delta must be a numeric"):
        lspb_min_time("1", 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="v_max must be a numeric"):
        lspb_min_time(1.0, True, 1.0)
