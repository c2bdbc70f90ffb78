"""Tests of planners.checker.verdict: a report's verdict and failing findings in a few words."""

from __future__ import annotations

import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.checker.verdict import failing_findings, finding_note, verdict


@pytest.fixture(scope="module")
def move():
    robot = get_robot("paddle4")
    return problems.PointToPoint(robot, q_start=robot.home, q_goal=[0.95, 0.3, 0.2, -0.4])


def test_a_passing_report_has_no_failing_findings(move):
    report = check(planners.Quintic().plan(move), move)
    assert report.ok
    assert verdict(report) == "pass"
    assert failing_findings(report) == "-"
    assert failing_findings(report, none="none") == "none"


def test_a_jump_reads_unbounded_and_every_failing_finding_is_listed_in_order(move):
    report = check(planners.LSPB().plan(move), move)  # acceleration jumps: jerk unbounded
    assert verdict(report) == "FAIL"
    names = [f.name for f in report.violations]
    assert "jerk" in names
    text = failing_findings(report)
    assert text == ", ".join(finding_note(f) for f in report.violations)
    assert "jerk (unbounded: a jump)" in text.split(", ")


def test_a_finite_excess_reads_as_its_share_of_the_limit(move):
    robot = move.robot
    traj = planners.Cubic().plan(move)
    share = check(traj, move, quantities=["velocity"])["velocity"].ratio  # about 0.97
    slower = problems.PointToPoint(
        robot, q_start=move.q_start, q_goal=move.q_goal, limits=robot.limits.scaled(0.5)
    )
    report = check(traj, slower, quantities=["velocity"])
    finding = report["velocity"]
    assert finding.ratio == pytest.approx(2.0 * share, rel=1e-9)
    expected = f"velocity ({round(200.0 * share)}%)"
    assert failing_findings(report) == expected
    assert finding_note(finding) == expected


def test_anything_but_a_report_or_a_finding_is_refused(move):
    report = check(planners.Quintic().plan(move), move)
    with pytest.raises(InvalidInputError, match=r"report must be a planners\.checker Report"):
        verdict(report.summary())
    with pytest.raises(InvalidInputError, match="report must be"):
        failing_findings(None)
    with pytest.raises(InvalidInputError, match="finding must be"):
        finding_note("velocity")
    with pytest.raises(InvalidInputError, match="none must be a string"):
        failing_findings(report, none=None)
