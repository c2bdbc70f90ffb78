"""Tests of planners.piecewise: checked pieces, Hermite interpolation, joining, deferred builds."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Phase, Trajectory


def _random_states(seed: int, m: int = 6, n: int = 3):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.5, m - 1))])
    return t, rng.normal(size=(m, n)), rng.normal(size=(m, n)), rng.normal(size=(m, n))


@pytest.mark.parametrize("with_acceleration", [False, True])
def test_hermite_meets_every_state_and_derivatives_agree_with_finite_differences(with_acceleration):
    t, q, qd, qdd = _random_states(1)
    traj = Trajectory.from_hermite(t, q, qd, qdd if with_acceleration else None)
    sample = traj.sample(t)
    np.testing.assert_allclose(sample.q, q, atol=1e-12)
    np.testing.assert_allclose(sample.qd, qd, atol=1e-11)
    if with_acceleration:
        np.testing.assert_allclose(sample.qdd, qdd, atol=1e-9)
    inner = np.linspace(0.01, traj.duration - 0.01, 97)
    h = 1e-6
    plus, minus = traj.sample(inner + h), traj.sample(inner - h)
    # Away from breakpoints the polynomial derivatives are exact; central differences agree.
    mask = np.min(np.abs(inner[:, None] - t[None, :]), axis=1) > 2 * h
    np.testing.assert_allclose(
        ((plus.q - minus.q) / (2 * h))[mask], traj.sample(inner).qd[mask], atol=1e-6
    )
    np.testing.assert_allclose(
        ((plus.qdd - minus.qdd) / (2 * h))[mask], traj.sample(inner).jerk[mask], atol=1e-4
    )


@pytest.mark.parametrize(
    ("breakpoints", "coefficients", "match"),
    [
        ([0.0, 1.0], np.zeros((2, 1, 1)), "one row per segment"),
        ([0.5, 1.0], np.zeros((1, 1, 1)), "start at 0"),
        ([0.0, 1.0, 1.0], np.zeros((2, 1, 1)), "strictly increase"),
        ([0.0, 1.0], [[[np.nan]]], "finite"),
        ([0.0, 1.0], np.zeros((1, 2)), "shape"),
        ([0.0, 1e300], [[[0.0]]], r"<= 86400 s, got 1e\+300 s"),
    ],
)
def test_bad_construction_is_rejected(breakpoints, coefficients, match):
    with pytest.raises(InvalidInputError, match=match):
        Trajectory(breakpoints, coefficients)
    # as float arrays (the shorter path of validated_pieces), the same error
    with pytest.raises(InvalidInputError, match=match):
        Trajectory(np.array(breakpoints, dtype=float), np.array(coefficients, dtype=float))


@pytest.mark.parametrize(
    ("breakpoints", "coefficients", "match"),
    [
        ([0.0, np.inf], np.zeros((1, 2, 1)), "finite"),
        ([0.0, np.nan, 2.0], np.zeros((2, 2, 1)), "finite"),
        ([0.0, 2.0, 1.0], np.zeros((2, 2, 1)), "strictly increase"),
        ([0.0, 1.0], np.array([[[1.0], [np.inf]]]), "finite"),
        ([0.0, 1.0], np.array([[[np.inf], [-np.inf]]]), "finite"),
        ([0.0, 1.0], np.zeros((1, 0, 2)), "at least one term"),
    ],
)
def test_bad_float_arrays_are_rejected(breakpoints, coefficients, match):
    with pytest.raises(InvalidInputError, match=match):
        Trajectory(np.array(breakpoints), coefficients)


def test_float_arrays_and_lists_give_the_same_read_only_copies():
    rng = np.random.default_rng(11)
    knots = np.array([0.0, 0.4, 1.1])
    coefficients = rng.normal(size=(2, 4, 3))
    huge = np.full((2, 4, 3), 1e308)  # finite, though their sum is not
    for array in (coefficients, huge):
        fast = Trajectory(knots, array)
        slow = Trajectory(knots.tolist(), array.tolist())
        np.testing.assert_array_equal(fast.breakpoints, slow.breakpoints)
        np.testing.assert_array_equal(fast.coefficients, slow.coefficients)
        assert not fast.coefficients.flags.writeable and not fast.breakpoints.flags.writeable
    before = coefficients.copy()
    traj = Trajectory(knots, coefficients)
    coefficients[:] = 0.0
    knots[1] = 0.5
    np.testing.assert_array_equal(traj.coefficients, before)
    assert traj.breakpoints[1] == 0.4


def test_derivatives_are_taken_on_first_sampling():
    rng = np.random.default_rng(12)
    coefficients = rng.normal(size=(1, 6, 2))
    traj = Trajectory(np.array([0.0, 1.5]), coefficients)
    t = np.linspace(0.0, 1.5, 7)
    sample = traj.sample(t)
    for order, values in enumerate((sample.q, sample.qd, sample.qdd, sample.jerk)):
        expected = [
            np.polynomial.polynomial.polyval(t, np.polynomial.polynomial.polyder(c, order))
            for c in coefficients[0].T
        ]
        np.testing.assert_allclose(values, np.array(expected).T, rtol=1e-12, atol=1e-12)
    assert len(traj._coeffs) == 4 and traj.degree == 5


def test_then_shifts_time_and_phases_and_raises_degree():
    first = Trajectory([0.0, 1.0], [[[0.0], [1.0]]], phases=[Phase("ramp", 0.0, 1.0)])
    second = Trajectory.constant([1.0], 0.5, phases=[Phase("hold", 0.0, 0.5)])
    joined = first.then(second)
    assert joined.duration == pytest.approx(1.5)
    assert [p.name for p in joined.phases] == ["ramp", "hold"]
    assert joined.phase("hold").t_start == pytest.approx(1.0)
    np.testing.assert_allclose(joined.sample([0.5, 1.2]).q[:, 0], [0.5, 1.0])
    with pytest.raises(InvalidInputError, match="1 and 2 joints"):
        first.then(Trajectory.constant([0.0, 0.0], 1.0))


def test_sequence_names_one_phase_per_group_of_pieces():
    ramp = Trajectory([0.0, 1.0], [[[0.0], [1.0]]])
    hold = Trajectory.constant([1.0], 0.5)
    traj = Trajectory.sequence([("idle", []), ("ramp", [ramp]), ("rest", [hold, hold])])
    assert [(p.name, p.t_start, p.t_end) for p in traj.phases] == [
        ("idle", 0.0, 0.0),
        ("ramp", 0.0, 1.0),
        ("rest", 1.0, 2.0),
    ]
    np.testing.assert_allclose(traj.sample([0.5, 1.7]).q[:, 0], [0.5, 1.0])
    with pytest.raises(InvalidInputError, match="at least one piece"):
        Trajectory.sequence([("idle", [])])


def test_deferred_build_that_does_not_fit_is_rejected_on_first_use():
    lazy = Trajectory.deferred(2.0, 3, lambda: ([0.0, 1.0], np.zeros((1, 1, 3))))
    with pytest.raises(InvalidInputError, match=r"deferred trajectory of 2\.0 s"):
        lazy.sample(0.5)
