"""Tests of planners.checker.checking: check's inputs, its errors, its speed, its trust."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, Task, quintic

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.checker import QUANTITIES, check
from optraj.planners.trajectory import Phase
from optraj.problems import BoundaryState, ToolContact


def test_bad_input_raises_typed_errors(paddle, sawyer):
    trajectory = quintic(Q0, Q0 + DELTA, T)
    with pytest.raises(InvalidInputError, match=r"planners\.Trajectory"):
        check("not a trajectory", paddle)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"robots\.Robot or a problem"):
        check(trajectory, object())
    with pytest.raises(InvalidInputError, match="4 joints"):
        check(trajectory, sawyer)
    with pytest.raises(UnknownNameError, match="velocity") as info:
        check(trajectory, paddle, quantities=["speed"])
    assert info.value.known == QUANTITIES
    with pytest.raises(InvalidInputError, match="rate"):
        check(trajectory, paddle, rate=0.0)
    bad = Task(paddle, (BoundaryState("start", np.zeros(3), np.zeros(4)),))
    with pytest.raises(InvalidInputError, match="length 4"):
        check(trajectory, bad)
    with pytest.raises(InvalidInputError, match="cannot check"):
        check(trajectory, Task(paddle, ("not a constraint",)))


@pytest.mark.parametrize(
    ("rate", "match"),
    [
        (True, "rate"),
        ("1000", "rate"),
        (-1.0, "rate must be > 0 Hz"),
        (1e9, r"rate must be <= 1e\+06 Hz"),
        (math.nan, "finite"),
    ],
)
def test_a_bad_rate_raises_a_typed_error(paddle, rate, match):
    # rate=True is no number; rate=1e9 would ask for gigabytes of samples.
    with pytest.raises(InvalidInputError, match=match):
        check(quintic(Q0, Q0 + DELTA, T), paddle, rate=rate)


@pytest.mark.slow
def test_a_rate_beyond_the_sample_budget_names_a_rate_that_fits(paddle):
    day = quintic(Q0, Q0 + DELTA, 86_400.0)
    with pytest.raises(InvalidInputError, match=r"rate 1000 Hz .* rate <= \d") as info:
        check(day, paddle)
    assert info.value.name == "rate"
    assert check(day, paddle, rate=10.0).trajectory.samples == 864_001


def test_metadata_claims_are_ignored(paddle):
    fast = quintic(Q0, Q0 + DELTA, 0.2, metadata={"status": "ok", "feasible": True})
    assert not check(fast, paddle)["velocity"].ok  # 1.875 x 0.5 / 0.2 = 4.7 rad/s > 3


def test_three_second_sawyer_check_is_fast(sawyer, pool_shot):
    trajectory = quintic(
        np.asarray(sawyer.home),
        pool_shot.q_contact,
        3.0,
        phases=[Phase("strike", 3.0 - pool_shot.window, 3.0)],
    )
    elapsed = []
    for _ in range(3):
        started = time.perf_counter()
        report = check(trajectory, pool_shot)
        elapsed.append(time.perf_counter() - started)
    assert report.trajectory.samples >= 3001
    assert min(elapsed) < 0.5, elapsed


def test_malformed_quantities_and_constraint_lists_raise_typed_errors(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T, phases=[Phase("strike", 1.5, 2.0)])
    with pytest.raises(InvalidInputError, match="quantities"):
        check(trajectory, paddle, quantities=5)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="iterable of constraints"):
        check(trajectory, Task(paddle, 5))  # type: ignore[arg-type]


def test_public_names_are_importable_from_the_package():
    import optraj.planners.checker as checker
    from optraj import planners

    for name in checker.__all__:
        assert getattr(checker, name) is not None, name
    assert planners.check is checker.check and planners.Report is checker.Report
    assert checker.MAX_RATE == 1e6 and checker.STRIKE_WINDOW_TOLERANCE == 1e-6


def test_repeated_finding_names_are_numbered(paddle):
    point = paddle.tool_position(Q0 + DELTA)
    twice = tuple(ToolContact(position=point, time=T) for _ in range(2))
    report = check(quintic(Q0, Q0 + DELTA, T), Task(paddle, twice))
    assert report.names[-2:] == ("contact", "contact (2)")
    assert report["contact"].value == report["contact (2)"].value < 1e-12
