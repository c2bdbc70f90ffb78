"""Tests of planners.strike.contact: choose_contact and contact_choices, their input.

The geometry of the choices is tested with their modules (test_pool_contact.py,
test_paddle_contact.py), the ratio with test_twist_ratio.py.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from conftest import get_robot, race
from strike_support import pool_shots

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.strike.contact import ContactChoice, choose_contact, contact_choices


def test_pool_choice_is_reproducible_for_a_seed():
    problem, again = (next(pool_shots(1, speed=1.0, seed=21)) for _ in range(2))
    assert problem is not again  # two searches, not one remembered answer
    first, second = choose_contact(problem, seed=4), choose_contact(again, seed=4)
    np.testing.assert_array_equal(first.q, second.q)
    np.testing.assert_array_equal(first.qd, second.qd)
    assert (first.ratio, first.binding_joint, first.candidates) == (
        second.ratio,
        second.binding_joint,
        second.candidates,
    )


def test_pool_choice_is_the_same_from_concurrent_threads():
    problem = next(pool_shots(1, speed=1.0, seed=21))
    expected = choose_contact(problem, candidates=4)
    results: dict[int, ContactChoice] = {}

    def worker(k):
        results[k] = choose_contact(problem, candidates=4)

    assert race(worker, 3) == []
    for choice in results.values():
        np.testing.assert_array_equal(choice.q, expected.q)
        np.testing.assert_array_equal(choice.qd, expected.qd)


def test_choose_contact_rejects_other_problems_and_bad_settings():
    with pytest.raises(InvalidInputError, match="PickAndPlace") as info:
        choose_contact(problems.youbot_two_blocks())
    assert info.value.name == "problem"
    problem = problems.PaddleStrike(get_robot("paddle4"), ball=(1.0, 0.3, 0.4))
    for kwargs, name in (
        ({"candidates": 0}, "candidates"),
        ({"candidates": 2.5}, "candidates"),
        ({"seed": -1}, "seed"),
        ({"margin": 1.0}, "margin"),
        ({"margin": -0.1}, "margin"),
    ):
        with pytest.raises(InvalidInputError) as info:
            choose_contact(problem, **kwargs)
        assert info.value.name == name


def test_contact_choices_are_distinct_branches_led_by_the_chosen_one():
    problem = problems.sawyer_pool_shot(
        1.0, (0.770755805063373, 0.11771877321136866, -0.04053151295117215), 6.371000264362529
    )
    choices = contact_choices(problem, 4)
    assert len(choices) == 4
    np.testing.assert_array_equal(choices[0].q, choose_contact(problem).q)
    robot = problem.robot
    for choice in choices:
        assert choice.ratio <= 1.0
        np.testing.assert_allclose(robot.tool_position(choice.q), problem.contact_point, atol=1e-6)
        axis = robot.tool_pose(choice.q)[:3, 2]
        np.testing.assert_allclose(axis, problem.direction, atol=1e-6)
    for a, b in itertools.combinations(choices, 2):
        assert np.abs(a.q - b.q).max() > 0.1
    paddle = problems.ece486_paddle_strike()
    assert len(contact_choices(paddle, 3)) == 1
    with pytest.raises(InvalidInputError, match="count"):
        contact_choices(problem, 0)


def test_excluded_branches_are_left_out():
    problem = next(pool_shots(1, speed=1.0, seed=33))
    first = contact_choices(problem, 3)
    others = contact_choices(problem, 3, exclude=[first[0].q])
    for choice in others:
        assert np.abs(choice.q - first[0].q).max() > 0.1
    # The same search: the next branches of the first call come first.
    assert [c.q.tolist() for c in others[:2]] == [c.q.tolist() for c in first[1:]]
    # None excludes nothing; anything but configurations is named.
    assert [c.q.tolist() for c in contact_choices(problem, 3, exclude=None)] == [
        c.q.tolist() for c in first
    ]
    for bad, match in (
        (5, "exclude must be a sequence"),
        ([[0.0] * 3], r"exclude\[0\]"),
        (first[0].q, "put a single configuration in a list"),
    ):
        with pytest.raises(InvalidInputError, match=match):
            contact_choices(problem, 3, exclude=bad)


def test_an_answer_is_remembered_per_problem_and_given_as_a_copy():
    problem = next(pool_shots(1, speed=1.0, seed=22))
    first = choose_contact(problem)
    first.q[:] = 0.0  # the caller's copy: the remembered answer stays as it was
    second = choose_contact(problem)
    fresh = choose_contact(next(pool_shots(1, speed=1.0, seed=22)))
    np.testing.assert_array_equal(second.q, fresh.q)
    assert second.ratio == fresh.ratio and second.candidates == fresh.candidates
    assert choose_contact(problem, seed=5).candidates >= 1  # other arguments: another search


def test_a_refusal_is_remembered_and_raised_again():
    problem = next(pool_shots(1, speed=5.0, seed=23))  # beyond Sawyer's velocity limits
    with pytest.raises(InfeasibleError) as first:
        choose_contact(problem)
    with pytest.raises(InfeasibleError) as again:
        choose_contact(problem)
    assert str(again.value) == str(first.value) and first.value.max_speed < 5.0
    assert again.value.joint == first.value.joint and again.value.__traceback__ is not None


def test_a_remembered_answer_goes_with_its_problem():
    import gc
    import weakref

    refused = next(pool_shots(1, speed=5.0, seed=23))
    planned = next(pool_shots(1, speed=1.0, seed=24))
    with pytest.raises(InfeasibleError):
        choose_contact(refused)
    choose_contact(planned)
    gone = [weakref.ref(refused), weakref.ref(planned)]
    del refused, planned
    gc.collect()
    assert [ref() for ref in gone] == [None, None]  # nothing kept them alive
