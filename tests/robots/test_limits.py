"""Tests of robots.limits.JointLimits."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from optraj import robots
from optraj.errors import InvalidInputError, JointLimitError, UnknownNameError
from optraj.robots import JointLimits


def _limits(**overrides):
    fields = dict(
        names=("a", "b"),
        kinds=("rad", "m"),
        lower=[-1.0, 0.0],
        upper=[1.0, 0.5],
        velocity=[2.0, 0.3],
        acceleration=[5.0, 1.0],
        jerk=[100.0, 20.0],
        effort=[10.0, 50.0],
    )
    fields.update(overrides)
    return JointLimits(**fields)


def test_arrays_are_read_only_floats():
    limits = _limits()
    assert limits.velocity.dtype == float
    with pytest.raises(ValueError, match="read-only"):
        limits.velocity[0] = 9.0


def test_floats_mirror_the_arrays_and_follow_a_replace():
    limits = _limits()
    assert limits.floats["upper"] == (1.0, 0.5) and limits.floats["jerk"] == (100.0, 20.0)
    assert all(type(value) is float for value in limits.floats["effort"])
    faster = limits.scaled(0.5, ("velocity",))
    assert faster.floats["velocity"] == (1.0, 0.15)
    assert limits.floats["velocity"] == (2.0, 0.3)
    with pytest.raises(TypeError):
        limits.floats["velocity"] = (9.0, 9.0)  # read-only
    clone = pickle.loads(pickle.dumps(limits))  # the cached view is left out
    assert clone.floats == limits.floats


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        ({"lower": [1.0, 0.0]}, "'a': lower position limit 1 must be below the upper limit 1"),
        ({"velocity": [2.0, 0.0]}, "'b': velocity limit must be > 0, got 0"),
        ({"jerk": [2.0]}, r"jerk must have shape \(2,\)"),
        ({"kinds": ("rad", "deg")}, "kinds must hold"),
        ({"effort": [np.inf, 1.0]}, "finite"),
    ],
)
def test_bad_limits_are_rejected(overrides, match):
    with pytest.raises(InvalidInputError, match=match):
        _limits(**overrides)


def test_contains_and_check_position():
    limits = _limits()
    assert limits.contains([0.0, 0.25])
    np.testing.assert_array_equal(limits.contains([[0.0, 0.25], [0.0, 0.6]]), [True, False])
    assert limits.contains([0.0, 0.5 + 1e-9], tolerance=1e-8)
    with pytest.raises(
        JointLimitError, match=r"joint 'b' position 0.6 m is above the upper limit 0.5"
    ) as info:
        limits.check_position([0.0, 0.6])
    assert info.value.joint == "b"


def test_check_position_reports_the_worst_joint():
    with pytest.raises(JointLimitError) as info:
        _limits().check_position([1.5, 0.6])  # a exceeds by 0.5 rad, b by 0.1 m
    assert info.value.joint == "a"


def test_sample_covers_the_whole_range_and_is_seeded():
    limits = _limits(lower=[-10.0, 0.0], upper=[10.0, 0.5])
    a = limits.sample(np.random.default_rng(1), 2000)
    b = limits.sample(np.random.default_rng(1), 2000)
    np.testing.assert_array_equal(a, b)
    assert a.shape == (2000, 2)
    assert np.all(limits.contains(a))
    # Uniform over [-10, 10]: about 69 % of draws lie beyond +-pi.
    assert 0.64 < np.mean(np.abs(a[:, 0]) > np.pi) < 0.74


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rng": 0, "count": 3}, "numpy.random.Generator"),
        ({"rng": np.random.default_rng(0), "count": -1}, "count must be an integer >= 0"),
        ({"rng": np.random.default_rng(0), "count": 2.7}, "count must be an integer >= 0"),
    ],
)
def test_sample_rejects_bad_arguments(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        _limits().sample(**kwargs)


@pytest.mark.parametrize("tolerance", [float("nan"), -1e-3, "0.1", True])
def test_tolerance_must_be_a_finite_non_negative_number(tolerance):
    with pytest.raises(InvalidInputError, match="tolerance"):
        _limits().check_position([5.0, 5.0], tolerance=tolerance)
    with pytest.raises(InvalidInputError, match="tolerance"):
        _limits().contains([0.0, 0.0], tolerance=tolerance)


def test_names_must_be_strings():
    with pytest.raises(InvalidInputError, match="names must be a sequence of joint names"):
        _limits(names=None)
    with pytest.raises(InvalidInputError, match="names must be a sequence of joint names"):
        _limits(names="ab")


def test_unit_rejects_unknown_quantity_and_joint():
    with pytest.raises(UnknownNameError, match="speed"):
        _limits().unit("speed", 0)
    with pytest.raises(InvalidInputError, match="out of range"):
        _limits().unit("velocity", 2)


def test_units_follow_joint_kind():
    limits = _limits()
    assert limits.unit("velocity", 0) == "rad/s"
    assert limits.unit("effort", 1) == "N"


def test_scaled_limits_scale_only_the_chosen_quantities():
    limits = robots.load("sawyer").limits
    room = limits.scaled(0.8)
    np.testing.assert_allclose(room.velocity, 0.8 * limits.velocity)
    np.testing.assert_allclose(room.acceleration, 0.8 * limits.acceleration)
    np.testing.assert_allclose(room.jerk, 0.8 * limits.jerk)
    np.testing.assert_array_equal(room.effort, limits.effort)
    np.testing.assert_array_equal(room.upper, limits.upper)
    effort = limits.scaled(0.5, ("effort",))
    np.testing.assert_allclose(effort.effort, 0.5 * limits.effort)
    np.testing.assert_array_equal(effort.velocity, limits.velocity)
    with pytest.raises(InvalidInputError, match=r"factor must be in \[1e-06, 1\]"):
        limits.scaled(1.5)
    with pytest.raises(UnknownNameError, match="position"):
        limits.scaled(0.5, ("position",))


@pytest.mark.parametrize("quantities", ["velocity", 5])
def test_scaled_takes_a_tuple_of_quantity_names(quantities):
    # A bare name is refused, not taken letter by letter ("unknown scalable limit 'v'"), and
    # a number with a typed error, not a TypeError.
    limits = robots.load("sawyer").limits
    with pytest.raises(InvalidInputError, match=r"quantities must be a tuple of names"):
        limits.scaled(0.5, quantities)
