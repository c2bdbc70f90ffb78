"""Tests of planners.arrays.scalar: quintic and trapezoidal against closed forms and the Toolbox."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from optraj.errors import InvalidInputError
from optraj.planners.arrays.scalar import quintic, trapezoidal


def _quintic_closed_form(q0, qf, T, t):
    """Rest-to-rest quintic: q0 + d s(x), x = t / T, and its time derivatives."""
    x, d = np.asarray(t) / T, qf - q0
    return (
        q0 + d * (10 * x**3 - 15 * x**4 + 6 * x**5),
        d / T * (30 * x**2 - 60 * x**3 + 30 * x**4),
        d / T**2 * (60 * x - 180 * x**2 + 120 * x**3),
    )


def _trapezoid_closed_form(q0, qf, T, V, t):
    """Position of the trapezoid cruising at V, blends of tb = T - |qf - q0| / V."""
    d = qf - q0
    v = np.copysign(V, d)
    tb = T - abs(d) / V
    a = v / tb
    t = np.asarray(t)
    return np.where(
        t <= tb,
        q0 + 0.5 * a * t**2,
        np.where(t <= T - tb, q0 + v * (t - 0.5 * tb), qf - 0.5 * a * (T - t) ** 2),
    )


@pytest.mark.parametrize("t", [11, np.linspace(0.0, 1.0, 11)])
def test_quintic_documented_example(t):
    # The Toolbox's own example and test: quintic(1, 2, 11) at rest ends.
    tg = quintic(1, 2, t)
    assert np.all(np.diff(tg.q) > 0.0)
    assert tg.q[0] == 1.0
    np.testing.assert_allclose([tg.q[-1], tg.q[5]], [2.0, 1.5], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd[[0, -1]], 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qdd[[0, 5, -1]], 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.sum(tg.qdd), 0.0, rtol=0, atol=1e-12)
    assert tg.istime is (not isinstance(t, int))


def test_quintic_with_end_velocities_meets_them():
    tg = quintic(1, 2, 11, -1, 1)
    np.testing.assert_allclose([tg.q[0], tg.q[-1]], [1.0, 2.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose([tg.qd[0], tg.qd[-1]], [-1.0, 1.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose([tg.qdd[0], tg.qdd[-1]], 0.0, rtol=0, atol=1e-12)


def test_quintic_matches_the_closed_form_on_random_moves():
    rng = np.random.default_rng(36)
    for _ in range(50):
        q0, qf = rng.uniform(-3.0, 3.0, 2)
        T = rng.uniform(0.1, 10.0)
        t = np.sort(np.concatenate([[0.0, T], rng.uniform(0.0, T, 20)]))
        tg = quintic(q0, qf, t)
        for got, want in zip(
            (tg.q, tg.qd, tg.qdd), _quintic_closed_form(q0, qf, T, t), strict=True
        ):
            np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * (1 + abs(qf - q0)))
        peak = np.max(np.abs(tg.trajectory.sample(np.linspace(0.0, T, 1001)).qd))
        np.testing.assert_allclose(peak, 15.0 / 8.0 * abs(qf - q0) / T, rtol=1e-9)


def test_quintic_with_moving_ends_solves_the_six_end_conditions():
    rng = np.random.default_rng(7)
    for _ in range(20):
        q0, qf, v0, v1 = rng.uniform(-2.0, 2.0, 4)
        T = rng.uniform(0.5, 5.0)
        # The 6x6 end conditions of the Toolbox's quintic_func, solved here directly.
        matrix = np.array(
            [
                [1, 0, 0, 0, 0, 0],
                [0, 1, 0, 0, 0, 0],
                [0, 0, 2, 0, 0, 0],
                [1, T, T**2, T**3, T**4, T**5],
                [0, 1, 2 * T, 3 * T**2, 4 * T**3, 5 * T**4],
                [0, 0, 2, 6 * T, 12 * T**2, 20 * T**3],
            ]
        )
        c = np.linalg.solve(matrix, [q0, v0, 0.0, qf, v1, 0.0])
        t = np.linspace(0.0, T, 13)
        tg = quintic(q0, qf, t, v0, v1)
        np.testing.assert_allclose(tg.q, np.polyval(c[::-1], t), rtol=1e-9, atol=1e-9)


def test_quintic_refuses_bad_numbers_naming_them():
    with pytest.raises(InvalidInputError, match="q0 must be finite"):
        quintic(np.nan, 1.0, 5)
    with pytest.raises(InvalidInputError, match="qdf"):
        quintic(0.0, 1.0, 5, 0.0, "fast")
    with pytest.raises(InvalidInputError, match="t must strictly increase"):
        quintic(0.0, 1.0, [0.0, 2.0, 1.0])


@pytest.mark.parametrize("t", [11, np.linspace(0.0, 1.0, 11)])
def test_trapezoidal_documented_example(t):
    tg = trapezoidal(1.0, 2.0, t)
    T = 10.0 if isinstance(t, int) else 1.0
    assert np.all(np.diff(tg.q) > 0.0)
    np.testing.assert_allclose(tg.q[[0, 5, -1]], [1.0, 1.5, 2.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd[[0, -1]], 0.0, rtol=0, atol=1e-12)
    assert np.all(tg.qd >= 0.0)
    np.testing.assert_allclose(np.sum(tg.qdd), 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose([tg.tblend, tg.V], [T / 3.0, 1.5 / T], rtol=1e-12)
    np.testing.assert_allclose(np.max(tg.qd), 1.5 / T, rtol=1e-12)


def test_trapezoidal_with_a_given_speed_cruises_at_it():
    # The Toolbox's test: trapezoidal(1, 2, 11, 0.2) has sd[5] = 0.2 (a triangle).
    tg = trapezoidal(1.0, 2.0, 11, 0.2)
    np.testing.assert_allclose([tg.q[0], tg.q[-1], tg.qd[5]], [1.0, 2.0, 0.2], rtol=0, atol=1e-12)
    assert tg.tblend == pytest.approx(5.0)


def test_trapezoidal_peak_is_v_on_random_moves():
    rng = np.random.default_rng(2026)
    for _ in range(100):
        q0, qf = rng.uniform(-3.0, 3.0, 2)
        T = rng.uniform(0.1, 10.0)
        dist = abs(qf - q0)
        V = rng.uniform(1.001, 2.0) * dist / T * rng.choice([-1.0, 1.0])  # sign ignored
        t = np.linspace(0.0, T, 201)
        tg = trapezoidal(q0, qf, t, V)
        np.testing.assert_allclose(tg.q, _trapezoid_closed_form(q0, qf, T, abs(V), t), atol=1e-9)
        np.testing.assert_allclose(tg.V, np.copysign(abs(V), qf - q0), rtol=1e-12)
        dense = tg.trajectory.sample(np.linspace(0.0, T, 2001)).qd[:, 0]
        np.testing.assert_allclose(np.max(np.abs(dense)), abs(V), rtol=1e-9)
        np.testing.assert_allclose(tg.tblend, T - dist / abs(V), rtol=1e-9)


def test_trapezoidal_refuses_speeds_outside_the_toolbox_bounds():
    t = np.linspace(0.0, 1.0, 11)
    with pytest.raises(
        InvalidInputError, match=r"V = 1e-09 is too small.*\|qf - q0\| / T = 1"
    ) as e:
        trapezoidal(1.0, 2.0, t, V=1e-9)
    assert e.value.name == "V"
    with pytest.raises(
        InvalidInputError, match=r"V = 1e\+19 is too large.*<= 2 \|qf - q0\| / T = 2"
    ):
        trapezoidal(1.0, 2.0, t, V=1e19)
    with pytest.raises(InvalidInputError, match="too small"):
        trapezoidal(1.0, 2.0, t, V=1.0)  # a blend of zero time
    tg = trapezoidal(1.0, 2.0, t, V=2.0)  # the triangle is the upper bound itself
    assert tg.tblend == pytest.approx(0.5)
    with pytest.raises(InvalidInputError, match="V must be finite"):
        trapezoidal(1.0, 2.0, t, V=np.nan)
    with pytest.raises(InvalidInputError, match="t must span at least 3e-06 s"):
        trapezoidal(1.0, 2.0, [0.0, 1e-6], V=2e6)


def test_trapezoidal_without_motion_holds_still():
    tg = trapezoidal(0.5, 0.5, 5, V=3.0)
    np.testing.assert_array_equal(tg.q, 0.5)
    np.testing.assert_array_equal(tg.qd, 0.0)
    assert (tg.tblend, tg.V) == (0.0, 0.0)


@pytest.mark.slow
def test_scalar_profiles_agree_with_the_robotics_toolbox(rtb):
    rng = np.random.default_rng(5)
    for _ in range(20):
        q0, qf, v0, v1 = rng.uniform(-2.0, 2.0, 4)
        t = np.linspace(0.0, rng.uniform(0.5, 5.0), 31)
        for args in ((q0, qf, 21, v0, v1), (q0, qf, t, v0, v1)):
            ours, theirs = quintic(*args), rtb.quintic(*args)
            for got, want in zip(
                (ours.q, ours.qd, ours.qdd), (theirs.q, theirs.qd, theirs.qdd), strict=True
            ):
                np.testing.assert_allclose(got, want, rtol=1e-7, atol=1e-7)
        V = rng.uniform(1.01, 2.0) * abs(qf - q0) / t[-1]
        for args in ((q0, qf, 21), (q0, qf, t), (q0, qf, t, V)):
            ours, theirs = trapezoidal(*args), rtb.trapezoidal(*args)
            np.testing.assert_allclose(ours.q, theirs.q, rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(ours.qd, theirs.qd, rtol=1e-9, atol=1e-9)
            assert ours.tblend == pytest.approx(theirs.tblend, rel=1e-9)
            # The acceleration jumps at the blends' ends: each side takes its own segment.
            away = np.abs(ours.t[:, None] - [theirs.tblend, ours.t[-1] - theirs.tblend]).min(1)
            np.testing.assert_allclose(ours.qdd[away > 1e-9], theirs.qdd[away > 1e-9], atol=1e-9)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(
    q0=st.floats(allow_nan=True, allow_infinity=True, width=64),
    qf=st.floats(-1e6, 1e6),
    end=st.floats(1e-7, 1e5),
    V=st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True)),
)
def test_any_numbers_give_finite_samples_or_a_typed_error(q0, qf, end, V):
    for make in (lambda: quintic(q0, qf, [0.0, end]), lambda: trapezoidal(q0, qf, [0.0, end], V)):
        try:
            tg = make()
        except InvalidInputError:
            continue
        assert all(np.all(np.isfinite(v)) for v in (tg.q, tg.qd, tg.qdd))
