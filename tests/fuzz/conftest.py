"""Hypothesis profiles of the fuzz suite, and the per-test record ``benchmarks/fuzz.py`` reads.

Profiles (chosen by ``FUZZ_PROFILE``, default ``default``):

* ``default``: the plain ``pytest`` run; derandomized (the same cases every run), no
  deadline (no wall-time judgement on a shared machine), no example database.
* ``fuzz``: ``make fuzz``; random cases from the seed given to pytest
  (``--hypothesis-seed``), and a per-case deadline of ``FUZZ_DEADLINE`` seconds (30 by
  default): a refusal that takes longer fails its property.

With ``FUZZ_REPORT`` set to a file path, the session writes there, as JSON, each test's
case count, time, outcomes and, for a failure, pytest's report with hypothesis's
falsifying example.
"""

from __future__ import annotations

import json
import os
from datetime import timedelta
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

from fuzz import budget

_SLOW_CHECKS = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]

settings.register_profile(
    "default",
    derandomize=True,
    deadline=None,
    database=None,
    print_blob=True,
    suppress_health_check=_SLOW_CHECKS,
)
settings.register_profile(
    "fuzz",
    derandomize=False,
    deadline=timedelta(seconds=float(os.environ.get("FUZZ_DEADLINE", "30"))),
    database=None,
    print_blob=True,
    suppress_health_check=_SLOW_CHECKS,
)
settings.load_profile("fuzz" if budget.PROFILE == "fuzz" else "default")

_FAILURES: dict[str, str] = {}
_KNOWN: dict[str, str] = {}


@pytest.fixture(autouse=True)
def _current_test(request: pytest.FixtureRequest) -> None:
    """Let :func:`fuzz.budget.recorded` file each case under the running test."""
    budget.CURRENT[0] = request.node.nodeid


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    """Keep the text of each failure (the falsifying example) for the fuzz report, and of
    each expected failure (a known defect, marked xfail) apart."""
    if report.failed:
        _FAILURES[report.nodeid] = report.longreprtext
    elif report.skipped and hasattr(report, "wasxfail") and report.when == "call":
        _KNOWN[report.nodeid] = f"{report.wasxfail}\n\n{report.longreprtext}"


def pytest_sessionfinish(session: pytest.Session) -> None:
    """Write the record for ``benchmarks/fuzz.py`` when ``FUZZ_REPORT`` names a file."""
    target = os.environ.get("FUZZ_REPORT")
    if not target:
        return
    record = {
        node: {
            "cases": stats.cases,
            "seconds": stats.seconds,
            "slowest": stats.slowest,
            "slowest_refusal": stats.slowest_refusal,
            "outcomes": dict(stats.outcomes),
            "failure": _FAILURES.get(node),
            "known": _KNOWN.get(node),
        }
        for node, stats in budget.STATS.items()
    }
    for node, text in _FAILURES.items():
        record.setdefault(node, {"cases": 0, "failure": text})
    for node, text in _KNOWN.items():
        record.setdefault(node, {"cases": 0, "known": text})
    Path(target).write_text(json.dumps(record, indent=1, default=str))
