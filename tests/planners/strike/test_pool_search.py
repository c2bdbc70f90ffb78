"""Tests of planners.strike.pool_search: a pool window's room to turn at the position limits."""

from __future__ import annotations

import math

import numpy as np
from strike_support import pool_shots, turn_ratio

from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.pool_search import PoolSearch


def test_turn_estimate_matches_its_formula_and_ranks_cornered_contacts_last():
    checked = 0
    for problem in pool_shots(6, speed=1.0, seed=31):
        choice = choose_contact(problem)
        search = PoolSearch(problem)
        window = search.window(choice.q)
        np.testing.assert_allclose(
            problem.speed * window.turn, turn_ratio(problem, choice.q), rtol=1e-7
        )
        # The choice has room to turn whenever some contact found had it.
        assert problem.speed * window.turn <= 1.0 or choice.ratio > 0.9
        checked += 1
    assert checked == 6


def test_a_joint_leaving_a_limit_it_sits_on_has_no_room_to_turn():
    problem = next(pool_shots(1, speed=1.0, seed=32))
    search = PoolSearch(problem)
    limits = problem.limits
    contact = (limits.lower + limits.upper) / 2
    entry, leave = contact.copy(), contact.copy()
    entry[0] = limits.lower[0]  # on its lower limit at the entry, moving up into the window
    contact[0] = limits.lower[0] + 0.01
    assert search.turn(entry, contact, leave) == math.inf
    entry[0] = limits.lower[0] + 0.011  # moving slowly down: the whole range behind it
    leave[0] = contact[0] + 0.005  # turned round inside the window, moving up fast
    rate = 0.005 / problem.follow_through
    expected = rate / math.sqrt(2 * limits.acceleration[0] * (limits.upper[0] - leave[0]))
    np.testing.assert_allclose(search.turn(entry, contact, leave), expected, rtol=1e-12)
