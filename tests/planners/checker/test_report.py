"""Tests of planners.checker.report: the report's API and the findings' validation."""

from __future__ import annotations

import dataclasses
import math

import pytest
from checker_support import DELTA, Q0, T, quintic

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.checker import Finding, check
from optraj.planners.checker.report import build_finding


def test_report_api(paddle):
    q1 = Q0.copy()
    q1[1] = paddle.limits.upper[1] + 0.05
    trajectory = quintic(Q0, q1, T, metadata={"planner": "by hand", "status": "ok"})
    report = check(trajectory, paddle, quantities="position")
    assert report.names == ("position",)
    assert report.trajectory.planner == "by hand"
    assert report.trajectory.duration == T
    assert report.trajectory.robot == "paddle4"
    assert not report.ok and report.violations == (report["position"],)
    with pytest.raises(UnknownNameError, match="position"):
        report["velocity"]
    with pytest.raises(UnknownNameError):
        report.passed("nothing")
    assert not report.passed()
    text = report.summary()
    assert "'by hand'" in text and "FAIL: 1 of 1" in text and "J2" in text
    with pytest.raises(dataclasses.FrozenInstanceError):
        report.findings[0].value = 0.0  # type: ignore[misc]
    with pytest.raises(InvalidInputError, match="NaN"):
        Finding("x", "task", math.nan, 1.0, 0.0, 0.0, None, None, "m", "", True)
    good = check(quintic(Q0, Q0 + DELTA, T), paddle)
    assert good.ok and good.passed() and "PASS: all 5 findings pass" in str(good)


def test_a_malformed_finding_raises_a_typed_error():
    with pytest.raises(InvalidInputError, match="must be a number"):
        Finding("x", "task", "1", 1.0, 0.0, 0.0, None, None, "m", "", True)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="ok must be True or False"):
        Finding("x", "task", 1.0, 1.0, 0.0, 0.0, None, None, "m", "", "no")  # type: ignore[arg-type]


def test_a_finding_that_is_not_a_number_fails_as_unbounded():
    finding = build_finding(
        "x", "limit", math.nan, 2.0, time=None, joint="J1", unit="m", detail="computed"
    )
    assert (finding.value, finding.margin, finding.ratio, finding.ok) == (
        math.inf,
        -math.inf,
        math.inf,
        False,
    )
    assert finding.detail == "computed (the value is not a number)"
    on_a_zero_limit = build_finding(
        "y", "task", 0.0, 0.0, time=1.0, joint=None, unit="m", detail=""
    )
    assert on_a_zero_limit.ratio == 0.0 and on_a_zero_limit.ok
