"""Tests of planners.profiles.via_segments: timing issues and their messages, phases."""

from __future__ import annotations

import math

import numpy as np
from conftest import get_robot

from optraj.errors import InfeasibleError
from optraj.planners.profiles.via_segments import (
    TimingIssue,
    floor_durations,
    limit_unit,
    segment_issues,
    segment_phases,
    worst_issue,
)


def _issue(**kwargs):
    fields = {
        "limit": "velocity",
        "where": "segment 2",
        "joint": 1,
        "required": 3.0,
        "allowed": 2.0,
        "unit": " rad/s",
        "segments": (1,),
        "growth": 1.5,
    }
    return TimingIssue(**(fields | kwargs))


def test_issues_report_joint_place_required_and_allowed():
    names = ("a", "b")
    error = _issue().error("lspb", names, "; hint")
    assert isinstance(error, InfeasibleError)
    assert (
        str(error)
        == "via points (lspb), segment 2: needs joint 'b' at 3 rad/s, limit 2 rad/s; hint"
    )
    assert (error.limit, error.joint, error.required, error.allowed) == ("velocity", "b", 3.0, 2.0)
    fit = _issue(limit="blend_time", joint=None, unit=" s", fit=True).error("lspb", names)
    assert str(fit) == "via points (lspb), segment 2 lasts 2 s, but its blends need 3 s"
    near = _issue(limit="via_tolerance", where="via point 1", unit=" rad").error("lspb", names)
    assert "the blend passes joint 'b' 3 rad from the via point, via_tolerance 2 rad" in str(near)


def test_the_worst_issue_has_the_largest_ratio():
    issues = [_issue(required=3.0), _issue(required=5.0), _issue(required=1.0, allowed=0.0)]
    assert issues[2].ratio == math.inf
    assert worst_issue(issues) is issues[2]
    assert worst_issue(issues[:2]) is issues[1]


def test_segment_issues_name_the_worst_joint_of_each_segment():
    limits = get_robot("paddle4").limits
    bound = np.array([1.0, 1.0, 1.0, 1.0])
    values = np.array([[0.5, 2.0, 3.0, 0.0], [1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 0.0, 1.5]])
    issues = segment_issues("velocity", values, bound, limits)
    assert [(issue.where, issue.joint, issue.growth) for issue in issues] == [
        ("segment 1", 2, 3.0),
        ("segment 3", 3, 1.5),
    ]
    assert issues[0].unit == limit_unit(limits, "velocity", 2) == f" {limits.unit('velocity', 2)}"
    assert limit_unit(limits, "velocity", None) == " s"


def test_durations_are_floored_and_phases_named_from_one():
    np.testing.assert_array_equal(floor_durations(np.array([2.0, 0.0, 1.0])), [2.0, 2e-3, 1.0])
    np.testing.assert_array_equal(floor_durations(np.zeros(2)), [1.0, 1.0])
    phases = segment_phases(np.array([0.0, 1.0, 2.5]))
    assert [(p.name, p.t_start, p.t_end) for p in phases] == [
        ("segment 1", 0.0, 1.0),
        ("segment 2", 1.0, 2.5),
    ]
