"""Tests of planners.checker.tool_contact: a tool point, axis and velocity at an instant."""

from __future__ import annotations

import math

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, Task, quintic

from optraj.planners.checker import check
from optraj.planners.trajectory import Phase
from optraj.problems import PaddleStrike, ToolContact


def test_paddle_contact_hit_and_missed_by_one_millimetre(paddle):
    problem = PaddleStrike(paddle, ball=(1.0, 0.3, 0.4), contact_angle=0.3)
    hit = check(quintic(problem.q_start, problem.q_contact, problem.contact_time), problem)
    assert hit.ok, hit.summary()
    contact = ("ball contact", "ball contact axis", "ball contact velocity")
    assert hit.names[-4:] == (*contact, "end state")
    assert hit["ball contact"].value < 1e-9
    assert hit["ball contact"].time == problem.contact_time

    high = problem.q_contact + np.array([1e-3, 0.0, 0.0, 0.0])  # J1 one millimetre up
    missed = check(quintic(problem.q_start, high, problem.contact_time), problem)
    assert {f.name for f in missed.violations} == {"ball contact", "end state"}
    assert missed["ball contact"].value == pytest.approx(1e-3, rel=1e-9)
    assert missed["ball contact axis"].ok


def test_contact_speed_and_missing_phase(paddle):
    problem = PaddleStrike(paddle, ball=(1.0, 0.3, 0.4), speed=0.5)
    report = check(quintic(problem.q_start, problem.q_contact, problem.contact_time), problem)
    velocity = report["ball contact velocity"]
    assert not velocity.ok  # arrives at rest instead of 0.5 m/s along the normal
    assert velocity.value == pytest.approx(0.5, rel=1e-9)
    assert velocity.unit == "m/s"

    grasp = ToolContact(position=np.zeros(3), phase="grasp_0", at="start", label="grasp 0")
    task = Task(paddle, (grasp,))
    report = check(quintic(Q0, Q0 + DELTA, T), task)
    assert report["grasp 0"].value == math.inf
    assert report["grasp 0"].detail == "phase 'grasp_0' missing"
    point = paddle.tool_position(Q0 + DELTA)
    task = Task(paddle, (ToolContact(position=point, phase="move", at="end", label="drop"),))
    moving = quintic(Q0, Q0 + DELTA, T, phases=[Phase("move", 0.0, T)])
    assert check(moving, task)["drop"].value < 1e-12
