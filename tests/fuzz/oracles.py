"""What a fuzz case must show: a typed refusal or a plan the independent checker passes.

The judges raise ``AssertionError`` (a property failure, which hypothesis shrinks and
reports) and return the outcome's name for the fuzz report: ``"planned"`` or the class
name of the ``OptrajError`` that refused the case.
"""

from __future__ import annotations

import contextlib
from typing import Any

import numpy as np
from hypothesis import note
from hypothesis.errors import InvalidArgument

from fuzz.strategies import PROMISES, PlannerSpec, ProblemSpec, finite_everywhere
from optraj import planners
from optraj.errors import OptrajError

__all__ = ["assert_nan_free", "check_rate", "judge_plan", "plan_or_refusal", "same_plan"]


def assert_nan_free(value: Any, what: str) -> None:
    """Fail when a NaN hides anywhere in ``value``."""
    where = finite_everywhere(value, what)
    assert where is None, f"NaN in {where}"


def _assert_trajectory_finite(traj: planners.Trajectory) -> None:
    """Polynomials finite, samples at the breakpoints and between them finite."""
    assert isinstance(traj, planners.Trajectory), f"plan returned {type(traj).__name__}"
    assert np.isfinite(traj.duration) and traj.duration >= 0.0, f"duration {traj.duration}"
    assert np.all(np.isfinite(traj.coefficients)), "non-finite coefficients"
    knots = np.asarray(traj.breakpoints)
    times = np.unique(np.concatenate([knots, (knots[:-1] + knots[1:]) / 2.0]))
    sample = traj.sample(times)
    for name in ("q", "qd", "qdd"):
        assert np.all(np.isfinite(getattr(sample, name))), f"non-finite {name} in a sample"
    assert_nan_free(traj.metadata, "metadata")


def _note(text: str) -> None:
    """Add ``text`` to hypothesis's report of a failing case (nothing outside a given test)."""
    with contextlib.suppress(InvalidArgument):  # a plain test, e.g. a known case
        note(text)


def plan_or_refusal(planner: Any, problem: Any) -> planners.Trajectory | OptrajError:
    """The planner's trajectory, or the typed error it raised (any other error propagates)."""
    try:
        return planner.plan(problem)
    except OptrajError as exc:
        return exc


#: Most samples one check takes [-]: a long trajectory is checked at a lower rate (the
#: checker bounds every polynomial segment exactly whatever the rate).
CHECK_SAMPLES = 200_000


def check_rate(traj: planners.Trajectory, rate: float = 1000.0) -> float:
    """``rate`` [Hz], lowered for a long trajectory to at most CHECK_SAMPLES samples."""
    return min(rate, CHECK_SAMPLES / max(traj.duration, 1e-9))


def judge_plan(planner_spec: PlannerSpec, problem_spec: ProblemSpec, rate: float = 1000.0) -> str:
    """Property 1 and 2: a typed error, or a finite trajectory that passes the checker.

    The checker judges the limit quantities the planner promises (``PROMISES``) and every
    task constraint of the problem.
    """
    try:
        problem = problem_spec.build()
    except OptrajError as exc:
        return f"problem {type(exc).__name__}"
    planner = planner_spec.build()
    result = plan_or_refusal(planner, problem)
    if isinstance(result, OptrajError):
        assert str(result).strip(), "a refusal without a message"
        return type(result).__name__
    _assert_trajectory_finite(result)
    report = planners.check(
        result, problem, rate=check_rate(result, rate), quantities=PROMISES[planner_spec.name]
    )
    assert_nan_free([(f.name, f.value, f.limit, f.margin) for f in report.findings], "report")
    _note(report.summary())
    assert report.ok, f"the checker fails the plan:\n{report.summary()}"
    return "planned"


def same_plan(first: planners.Trajectory | OptrajError, second: Any) -> None:
    """Property 3: two plans of one problem are identical (or the same refusal)."""
    if isinstance(first, OptrajError):
        assert isinstance(second, OptrajError), "refused once, planned once"
        assert type(first) is type(second) and str(first) == str(second), (first, second)
        return
    assert isinstance(second, planners.Trajectory), f"planned once, then {second!r}"
    assert np.array_equal(first.breakpoints, second.breakpoints), "breakpoints differ"
    assert np.array_equal(first.coefficients, second.coefficients), "coefficients differ"
    assert [(p.name, p.t_start, p.t_end) for p in first.phases] == [
        (p.name, p.t_start, p.t_end) for p in second.phases
    ], "phases differ"
