"""Tests of planners.checker.strike_line: strike window, schedule, speed, axis and contact."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, Task, no_nan, quintic

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import StrikeLine
from optraj.robots import Robot, solve_ik

STRIKE = ("strike window", "strike position", "strike speed", "strike axis", "contact")


def strike_motion(problem: problems.PoolStrike, factor: float = 1.0, step: float = 0.005):
    """The cue tip on the strike line at factor x the commanded speed, by IK and Hermite."""
    robot = problem.robot
    line = next(c for c in problem.constraints() if isinstance(c, StrikeLine))
    rotation = robot.tool_pose(problem.q_contact)[:3, :3]  # z along the shot, roll fixed
    times = np.arange(0.0, line.window + step / 2, step)
    qs, qds = [], []
    q = problem.q_contact
    for t in times:
        pose = np.eye(4)
        pose[:3, :3] = rotation
        pose[:3, 3] = line.point + factor * line.speed * (t - line.contact_delay) * line.direction
        q = solve_ik(robot, pose, q_near=q).q
        twist = np.concatenate([factor * line.speed * line.direction, np.zeros(3)])
        qs.append(q)
        qds.append(np.linalg.lstsq(robot.jacobian(q), twist, rcond=None)[0])
    return Trajectory.from_hermite(times, qs, qds, phases=[Phase("strike", 0.0, times[-1])])


def test_pool_strike_on_schedule_and_one_percent_fast(pool_shot):
    report = check(strike_motion(pool_shot), pool_shot)
    assert report.passed(*STRIKE), report.summary()
    assert report["contact"].time == pytest.approx(pool_shot.contact_delay)
    # This piece is only the strike: it does not start at rest at q_start.
    assert not report["start state"].ok

    fast = check(strike_motion(pool_shot, 1.01), pool_shot)
    speed = fast["strike speed"]
    assert not speed.ok and speed.unit == "-"
    assert speed.value == pytest.approx(0.01, rel=1e-2)
    schedule = fast["strike position"]
    assert not schedule.ok
    # 1 % of the 0.1 m run-up: 1 mm behind the schedule when the window opens.
    assert schedule.value == pytest.approx(1e-3, rel=1e-2)
    assert schedule.time == pytest.approx(0.0, abs=1e-9)
    assert fast.passed("contact", "strike axis", "strike window")


def test_strike_without_its_phase_fails_every_strike_finding(pool_shot):
    moving = strike_motion(pool_shot)
    bare = Trajectory(moving.breakpoints, moving.coefficients)
    report = check(bare, pool_shot)
    no_nan(report)
    for name in STRIKE:
        assert report[name].value == math.inf and not report[name].ok
        assert report[name].detail == "phase 'strike' missing"


def paddle_push(paddle: Robot, speed: float, contact: float, window: float) -> Task:
    """A strike along the paddle normal (+x at home): exactly what joint J3 does."""
    line = StrikeLine(
        phase="strike",
        point=paddle.tool_position(Q0),
        direction=np.array([1.0, 0.0, 0.0]),
        speed=speed,
        contact_delay=contact,
        window=window,
    )
    return Task(paddle, (line,))


def test_paddle_strike_line_is_exact_and_its_errors_are_measured(paddle):
    # J3 runs at 0.5 m/s through Q0 at t = 0.1 s; the strike window is [0, 0.3] s.
    c = np.zeros((1, 2, 4))
    c[0, 0] = Q0 - np.array([0.0, 0.0, 0.05, 0.0])
    c[0, 1, 2] = 0.5
    trajectory = Trajectory([0.0, 0.3], c, phases=[Phase("strike", 0.0, 0.3)])
    report = check(trajectory, paddle_push(paddle, 0.5, 0.1, 0.3))
    assert report.ok, report.summary()
    assert all(report[name].value < 1e-12 for name in STRIKE)

    late = check(trajectory, paddle_push(paddle, 0.5, 0.102, 0.3))  # contact 2 ms later
    assert late["contact"].value == pytest.approx(1e-3, rel=1e-9)
    assert late["contact"].time == pytest.approx(0.102)
    assert late["strike position"].value == pytest.approx(1e-3, rel=1e-9)
    assert late.passed("strike speed", "strike axis", "strike window")

    slow = check(trajectory, paddle_push(paddle, 0.5 / 1.01, 0.1, 0.3))
    assert slow["strike speed"].value == pytest.approx(0.01, rel=1e-9)
    drifting = c.copy()
    drifting[0, 1, 0] = 0.005  # J1 lifts the paddle at 1 % of the strike speed
    lifted = Trajectory([0.0, 0.3], drifting, phases=[Phase("strike", 0.0, 0.3)])
    across = check(lifted, paddle_push(paddle, 0.5, 0.1, 0.3))["strike speed"]
    assert across.value == pytest.approx(0.01, rel=1e-9)
    assert "across the line" in across.detail
    assert check(trajectory, paddle_push(paddle, 0.5, 0.1, 0.2))["strike window"].value == (
        pytest.approx(0.1)
    )


def test_malformed_strike_line_fields_raise_typed_errors(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T, phases=[Phase("strike", 1.5, 2.0)])
    line = StrikeLine("strike", np.zeros(3), np.array([1.0, 0.0, 0.0]), 1.0, 0.2, 0.5)
    for field, value, match in (
        ("speed", "fast", "StrikeLine.speed"),
        ("speed", 0.0, "StrikeLine.speed must be > 0 m/s"),
        ("contact_delay", None, "StrikeLine.contact_delay"),
        ("position_tolerance", -1.0, "StrikeLine.position_tolerance must be >= 0 m"),
        ("align_axis", 1, "StrikeLine.align_axis must be True or False"),
    ):
        bad = dataclasses.replace(line, **{field: value})
        with pytest.raises(InvalidInputError, match=match):
            check(trajectory, Task(paddle, (bad,)))
