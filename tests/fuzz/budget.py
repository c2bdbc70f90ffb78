"""How many cases each property runs, and what each case did (for the ``make fuzz`` report).

The default profile (a plain ``pytest``) runs each property's ``default`` count; the ``fuzz``
profile (``FUZZ_PROFILE=fuzz``, set by ``benchmarks/fuzz.py``) shares ``FUZZ_CASES`` cases
(100,000 by default) over the properties by the ``share`` of each, chosen from the measured
cost of a case so that the whole run takes about 30 minutes on 2 cores.
"""

from __future__ import annotations

import functools
import os
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ParamSpec

__all__ = ["PROFILE", "STATS", "Stats", "examples", "recorded"]

#: The hypothesis profile in use: ``"default"`` or ``"fuzz"``.
PROFILE = os.environ.get("FUZZ_PROFILE", "default")
#: Cases of a whole ``fuzz`` run.
TOTAL = int(os.environ.get("FUZZ_CASES", "100000"))

#: Per property: (cases of each test in the default profile, share of TOTAL for all of its
#: tests in the fuzz profile). The shares add up to 1.
PLAN: dict[str, tuple[int, float]] = {
    "plan": (16, 0.14),  # per planner x problem kind; about 50 ms a case
    "determinism": (10, 0.03),  # three plans a case; about 90 ms
    "refusal": (25, 0.05),  # problems built to be refused; about 50 ms
    "optimal control": (6, 0.003),  # IPOPT solves, 0.5-1.5 s a case (up to 13 s)
    "line": (6, 0.005),  # Cartesian lines, IK along the line; about 0.3 s a case
    "strike": (8, 0.02),  # paddle strikes; about 20 ms
    "controller": (20, 0.01),  # closed-loop runs; 0.1-0.6 s
    "trajectory": (40, 0.05),  # random piecewise polynomials; about 30 ms
    "malformed": (4, 0.492),  # per entry point; about 3 ms a case
    "cli argv": (120, 0.12),  # about 25 ms
    "cli file": (80, 0.08),  # about 30 ms
}


def examples(prop: str, tests: int = 1) -> int:
    """Cases for each of the ``tests`` tests of property ``prop`` in the active profile."""
    default, share = PLAN[prop]
    if PROFILE != "fuzz":
        return default
    return max(1, round(TOTAL * share / tests))


@dataclass
class Stats:
    """What the cases of one test did.

    Attributes:
        cases: Cases run (shrinking replays included).
        seconds: Their total wall time [s].
        slowest: The longest case [s].
        outcomes: Count of each outcome, e.g. ``"planned"`` or ``"InfeasibleError"``.
        slowest_refusal: The longest case that ended in a typed error [s].
    """

    cases: int = 0
    seconds: float = 0.0
    slowest: float = 0.0
    outcomes: Counter[str] = field(default_factory=Counter)
    slowest_refusal: float = 0.0


#: Stats by test node id; ``CURRENT`` is the running test's (set by the conftest).
STATS: dict[str, Stats] = {}
CURRENT = ["?"]

P = ParamSpec("P")


def recorded(function: Callable[P, str | None]) -> Callable[P, None]:
    """Count and time each call of a property body; its return value names the outcome.

    The body returns a short outcome name (``"planned"``, an error class name, ...) or None;
    the wrapper returns None, as hypothesis wants of a test.
    """

    def run(*args: P.args, **kwargs: P.kwargs) -> None:
        stats = STATS.setdefault(CURRENT[0], Stats())
        started = time.perf_counter()
        outcome: Any = "raised"
        try:
            outcome = function(*args, **kwargs)
        finally:
            spent = time.perf_counter() - started
            stats.cases += 1
            stats.seconds += spent
            stats.slowest = max(stats.slowest, spent)
            name = str(outcome) if outcome is not None else "passed"
            stats.outcomes[name] += 1
            if name.endswith("Error"):
                stats.slowest_refusal = max(stats.slowest_refusal, spent)

    return functools.wraps(function)(run)
