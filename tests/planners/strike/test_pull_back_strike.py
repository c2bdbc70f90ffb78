"""Tests of planners.strike.pull_back_strike: the pull-back + constant-speed strike."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.strike.pull_back_strike import PullBackStrike


def test_pull_back_strike_hits_the_line_but_needs_unbounded_acceleration():
    problem = problems.sawyer_pool_shot(speed=1.0)
    traj = PullBackStrike().plan(problem)
    assert [p.name for p in traj.phases] == ["pull back", "strike", "stop"]
    report = check(traj, problem)
    # On the line, at the speed, through the ball ...
    for name in ("strike window", "strike position", "strike speed", "strike axis", "contact"):
        assert report[name].ok, report.summary()
    # ... but the cue jumps from rest to 1 m/s and back: an impulse the arm cannot give.
    assert report["acceleration"].value == np.inf
    assert not report.ok


def test_pull_back_strike_rejects_other_problems():
    with pytest.raises(InvalidInputError, match="PoolStrike"):
        PullBackStrike().plan(problems.ece486_paddle_strike())
    with pytest.raises(InvalidInputError, match="hold_time"):
        PullBackStrike(hold_time=0.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"samples": -1}, "samples must be an integer >= 1"),
        ({"samples": 2.5}, "samples must be an integer"),
        ({"samples": True}, "samples must be an integer"),
        ({"samples": 10**9}, "samples must be an integer <= 100000"),
        ({"hold_time": "0.2"}, "hold_time must be a numeric"),
        ({"hold_time": 1e200}, "hold_time must be <= 86400 s"),
        ({"pull_back_time": 1e-200}, "duration must be >= 1e-06 s"),
    ],
)
def test_bad_settings_are_typed_errors(kwargs, match):
    # issue 32, defect 6: samples=-1 was an IndexError at planning time
    with pytest.raises(InvalidInputError, match=match):
        PullBackStrike(**kwargs)
