"""Tests of optraj.validation."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.validation import (
    as_array,
    as_batch,
    as_flag,
    as_fraction,
    as_number,
    as_positive,
    as_transform,
    as_vector,
)


def test_as_flag_takes_bools_only():
    assert as_flag(True, "feedforward") is True
    assert as_flag(np.bool_(False), "feedforward") is False
    for bad in (1, 0, "yes", None, 1.0):
        with pytest.raises(InvalidInputError, match=r"feedforward must be True or False"):
            as_flag(bad, "feedforward")


def test_as_vector_accepts_and_copies_lists():
    out = as_vector([1, 2, 3], "q", 3)
    assert out.dtype == float
    np.testing.assert_array_equal(out, [1.0, 2.0, 3.0])


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ([1, 2], r"q must have shape \(3,\), got shape \(2,\)"),
        ([1, np.nan, 2], "finite"),
        (["a", 1, 2], r"numeric array of shape \(3,\)"),
    ],
)
def test_as_vector_rejects(value, match):
    with pytest.raises(InvalidInputError, match=match) as info:
        as_vector(value, "q", 3)
    assert info.value.name == "q"


def test_as_batch_single_and_stack():
    one, single = as_batch([0.0, 1.0], "q", 2)
    assert single and one.shape == (1, 2)
    many, single = as_batch(np.zeros((5, 2)), "q", 2)
    assert not single and many.shape == (5, 2)
    with pytest.raises(InvalidInputError, match="shape"):
        as_batch([[0.0, 1.0], [1.0]], "q", 2)


def test_as_positive():
    assert as_positive(2, "speed", "m/s") == 2.0
    with pytest.raises(InvalidInputError, match="speed must be > 0 m/s, got -1 m/s"):
        as_positive(-1.0, "speed", "m/s")


def test_as_transform_checks_rotation_and_last_row():
    np.testing.assert_array_equal(as_transform(np.eye(4), "T"), np.eye(4))
    bad = np.eye(4)
    bad[3, 0] = 1.0
    with pytest.raises(InvalidInputError, match=r"T\[3\] must be \[0, 0, 0, 1\]"):
        as_transform(bad, "T")
    scaled = np.diag([2.0, 1.0, 1.0, 1.0])
    with pytest.raises(InvalidInputError, match="rotation matrix"):
        as_transform(scaled, "T")


def test_as_array_wildcard_shape():
    assert as_array(np.zeros((7, 3)), "points", (None, 3)).shape == (7, 3)


@pytest.mark.parametrize(
    "value",
    [True, ["1", "2", "3"], "abc", [10**400, 1, 1], None, [0, True, 1], ([0.5, False],)],
)
def test_bools_strings_and_overflow_are_not_numbers(value):
    shape = () if value is True or value is None or value == "abc" else (len(value),)
    with pytest.raises(InvalidInputError, match="numeric array"):
        as_array(value, "x", shape)


def test_as_fraction():
    assert as_fraction(1, "scale") == 1.0
    assert as_fraction(0.25, "scale") == 0.25
    assert as_fraction(1e-6, "scale") == 1e-6
    for bad in (0.0, -0.5, 1.5, 1e-300):
        with pytest.raises(InvalidInputError, match=r"scale must be in \[1e-06, 1\], got"):
            as_fraction(bad, "scale")
    with pytest.raises(InvalidInputError, match="finite"):
        as_fraction(float("nan"), "scale")


def test_counts_have_an_upper_bound_that_the_error_names():
    from optraj.validation import MAX_COUNT, as_count

    assert as_count(MAX_COUNT, "n") == MAX_COUNT
    with pytest.raises(InvalidInputError, match=r"n must be an integer <= 10000000, got 10000001"):
        as_count(MAX_COUNT + 1, "n")
    assert as_count(2**80, "seed", maximum=None) == 2**80


def test_counts_that_unroll_or_allocate_are_refused_before_any_work():
    from optraj import controllers, planners, problems
    from optraj.planners.strike.contact import choose_contact

    shot = problems.sawyer_pool_shot()
    with pytest.raises(InvalidInputError, match="active_set_changes must be an integer <= 64"):
        controllers.DiffIKQP(shot.robot, active_set_changes=10**6)
    with pytest.raises(InvalidInputError, match="candidates must be an integer <= 1000"):
        choose_contact(shot, candidates=10**6)
    with pytest.raises(InvalidInputError, match="dof must be an integer <= 1000"):
        planners.Trajectory.deferred(1.0, 2**63, lambda: ([0.0, 1.0], [[[0.0]]]))


def test_as_number_names_the_bound_and_the_unit():
    from optraj.validation import as_number

    assert as_number(2, "speed", "m/s", minimum=0.0, maximum=10.0) == 2.0
    with pytest.raises(InvalidInputError, match=r"speed must be <= 10 m/s, got 1e\+308 m/s"):
        as_number(1e308, "speed", "m/s", maximum=10.0)
    with pytest.raises(InvalidInputError, match=r"speed must be > 0 m/s, got 0 m/s"):
        as_number(0.0, "speed", "m/s", minimum=0.0, open_minimum=True)
    with pytest.raises(InvalidInputError, match=r"gap must be >= -1, got -2"):
        as_number(-2, "gap", minimum=-1.0)
    for not_a_number in (True, "2", None):
        with pytest.raises(InvalidInputError, match="numeric array"):
            as_number(not_a_number, "x")


def test_durations_have_physical_bounds():
    from optraj.validation import MAX_DURATION, MIN_DURATION, as_duration

    assert as_duration(2, "duration") == 2.0
    assert as_duration(MIN_DURATION) == MIN_DURATION
    assert as_duration(MAX_DURATION) == MAX_DURATION
    with pytest.raises(InvalidInputError, match=r"duration must be <= 86400 s, got 1e\+200 s"):
        as_duration(1e200)
    with pytest.raises(InvalidInputError, match=r"duration must be >= 1e-06 s, got 1e-200 s"):
        as_duration(1e-200)
    with pytest.raises(InvalidInputError, match="numeric array"):
        as_duration("2")


def test_as_choice_refuses_what_is_not_a_name():
    from optraj.errors import UnknownNameError
    from optraj.validation import as_choice

    assert as_choice("ipopt", "solver", ("ipopt", "sqpmethod")) == "ipopt"
    with pytest.raises(UnknownNameError, match=r"unknown solver 'ipop'.*did you mean 'ipopt'"):
        as_choice("ipop", "solver", ("ipopt", "sqpmethod"))
    for not_a_name in (np.array(["ipopt", "x"]), 3, None, ["ipopt"]):  # arrays made `in` fail
        with pytest.raises(InvalidInputError, match="solver must be a name, one of 'ipopt'"):
            as_choice(not_a_name, "solver", ("ipopt", "sqpmethod"))


def test_ndim_of_reads_ragged_lists_as_minus_one():
    from optraj.validation import ndim_of

    assert ndim_of(1.0) == 0
    assert ndim_of([[1.0, 2.0], [3.0, 4.0]]) == 2
    assert ndim_of([[1.0, 2.0], [3.0]]) == -1
    with pytest.raises(InvalidInputError, match="numeric array"):
        as_array([[1.0, 2.0], [3.0]], "gains", (None,))


def _outcome(check, *args):
    """A check's result, or the type and message of the error it raises."""
    try:
        return check(*args)
    except InvalidInputError as error:
        return (type(error), str(error), error.name)


def test_as_vector_fast_path_equals_as_array_on_seeded_random_input():
    # Float64 arrays and lists of floats take a path of their own; it must give what the
    # general one gives: the same values in a fresh array, or the same error.
    rng = np.random.default_rng(3501)
    for _ in range(300):
        values = rng.normal(size=int(rng.integers(0, 9))) * 10.0 ** float(rng.integers(-300, 300))
        if values.size and rng.random() < 0.4:
            values[rng.integers(values.size)] = rng.choice([np.nan, np.inf, -np.inf])
        for given in (values, values.tolist(), values[::-1], values[None, :]):
            for size in (None, values.size, values.size + 1):
                got = _outcome(as_vector, given, "v", size)
                want = _outcome(as_array, given, "v", (size,))
                if isinstance(want, tuple):
                    assert got == want
                else:
                    assert got.dtype == float and got.shape == want.shape
                    np.testing.assert_array_equal(got, want)
                    assert not np.shares_memory(got, given)


def test_as_number_takes_floats_without_numpy_and_refuses_the_same():
    rng = np.random.default_rng(3502)
    samples = [*rng.normal(size=50) * 1e3, np.nan, np.inf, -np.inf, 0.0, -0.0, 1e-6, 86_400.0]

    def check(x):
        return as_number(x, "t", "s", minimum=0.0, maximum=1e3)

    for value in samples:
        for given in (float(value), np.float64(value)):
            assert _outcome(check, given) == _outcome(check, np.array(value))
