"""Tests of planners.arrays.inputs: the time argument and joint vectors."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import MAX_STEPS, joint_vectors, time_base


def test_an_int_is_a_number_of_steps():
    base = time_base(5)
    np.testing.assert_array_equal(base.times, [0.0, 1.0, 2.0, 3.0, 4.0])
    assert base.end == 4.0
    assert base.istime is False
    assert time_base(np.int64(3)).end == 2.0


def test_a_normalised_int_spreads_the_samples_over_zero_to_one():
    base = time_base(5, normalised=True)
    np.testing.assert_allclose(base.times, [0.0, 0.25, 0.5, 0.75, 1.0], rtol=0, atol=0)
    assert base.end == 1.0
    assert base.istime is False


def test_a_time_vector_is_kept_and_ends_the_profile():
    base = time_base([0.5, 1.0, 3.0])
    np.testing.assert_array_equal(base.times, [0.5, 1.0, 3.0])
    assert base.end == 3.0
    assert base.istime is True


@pytest.mark.parametrize(
    ("t", "words"),
    [
        (1, "integer >= 2"),
        (MAX_STEPS + 1, f"<= {MAX_STEPS}"),
        (True, "int number of steps or a vector"),
        (2.0, "int number of steps or a vector"),
        ([[0.0, 1.0]], "int number of steps or a vector"),
        ([1.0], "at least 2 times"),
        ([-0.1, 1.0], "start at 0 s or later, got -0.1"),
        ([0.0, 1.0, 1.0], "strictly increase: t[2] = 1 s follows t[1] = 1 s"),
        ([0.0, 2.0, 1.0], "strictly increase"),
        ([0.0, np.nan], "finite"),
        ([0.0, 1e-9], "must end in [1e-06, 86400] s"),
        ([0.0, 1e6], "must end in [1e-06, 86400] s"),
        ("abc", "int number of steps or a vector"),
    ],
)
def test_bad_times_are_refused_naming_t_and_the_bound(t, words):
    with pytest.raises(InvalidInputError, match="t ") as caught:
        time_base(t)
    assert words in str(caught.value)
    assert caught.value.name == "t"


def test_joint_vectors_must_match_in_length():
    start, goal = joint_vectors([0, 1], [2.0, 3.0])
    np.testing.assert_array_equal(start, [0.0, 1.0])
    np.testing.assert_array_equal(goal, [2.0, 3.0])
    with pytest.raises(InvalidInputError, match=r"qf must have shape \(2,\)"):
        joint_vectors([0.0, 1.0], [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match="q0 must hold at least one"):
        joint_vectors([], [])
    with pytest.raises(InvalidInputError, match="q0 must be finite"):
        joint_vectors([np.inf], [0.0])
