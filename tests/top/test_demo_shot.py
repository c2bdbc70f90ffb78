"""Tests of the pool-shot sections of ``optraj demo`` (the whole demo: tests/top/test_cli.py)."""

from __future__ import annotations

import io

from optraj import planners, problems
from optraj.demo_shot import Attempt, planner_label, planner_section, short_reason
from optraj.errors import InfeasibleError, InvalidInputError


def test_short_reason_keeps_the_class_and_the_first_clause():
    exc = InvalidInputError(
        "the strike line needs joint 'j1' at 2.2 rad/s (velocity), limit 1.3 rad/s; more"
    )
    assert short_reason(exc) == (
        "InvalidInputError: the strike line needs joint 'j1' at 2.2 rad/s, limit 1.3 rad/s"
    )
    long = short_reason(InvalidInputError("x" * 300), width=40)
    assert len(long) == 40 and long.endswith("...")


def test_labels_say_what_a_planner_does():
    label = planner_label("pull-back", planners.PullBackStrike())
    assert label == "pull-back + constant-speed strike"
    assert planner_label("cubic", planners.Cubic()) == planners.Cubic().name


def _refusal(speed: float) -> InfeasibleError:
    return InfeasibleError(
        f"the strike line at {speed:g} m/s needs joint 'j1' at 2 rad/s (velocity), limit 1 rad/s",
        limit="velocity",
    )


def test_planners_refused_for_one_reason_share_one_line():
    shot = problems.sawyer_pool_shot(speed=0.3)
    seed = planners.PullBackStrike().plan(shot)
    attempts = [
        Attempt("pull-back", "pull-back + constant-speed strike", seed, planners.check(seed, shot)),
        Attempt("cubic", "cubic strike", error=_refusal(1.0)),
        Attempt("ruckig", "ruckig strike", error=_refusal(1.0)),
        Attempt("lspb", "lspb strike", error=_refusal(2.0)),
    ]
    out = io.StringIO()
    planner_section(shot, attempts, out)
    lines = out.getvalue().splitlines()
    assert lines[0] == "" and lines[1].startswith("what each planner did")
    assert "FAIL  it starts the strike line at full speed from rest" in lines[2]
    assert lines[3] == (
        "  cubic, ruckig strikes: refused, the strike line at 1 m/s needs joint 'j1' at 2 "
        "rad/s, limit 1 rad/s at the problem's contact configuration"
    )
    assert lines[4].startswith("  lspb strike: refused, the strike line at 2 m/s")
    # No plan passed: no line on why one succeeds.
    assert len(lines) == 5
