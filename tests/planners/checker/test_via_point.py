"""Tests of planners.checker.via_point: the closest approach to a via point, exactly."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, quintic

from optraj.planners.checker import check
from optraj.problems import Waypoints


def test_via_point_passed_between_samples_and_missed(paddle):
    a, c = Q0, Q0 + DELTA
    b = a + 0.3 * DELTA  # on the straight joint path, reached between two samples
    problem = Waypoints(paddle, [a, b, c], via_tolerance=1e-7)
    report = check(quintic(a, c, T), problem)
    via = report["via point 1"]
    assert via.ok, report.summary()
    assert via.value < 1e-9
    s = (via.time / T) ** 3 * (10 - 15 * via.time / T + 6 * (via.time / T) ** 2)
    assert s == pytest.approx(0.3, abs=1e-9)

    missed = b + np.array([0.0, 0.0, 0.01, 0.0])
    trajectory = quintic(a, missed, 1.0).then(quintic(missed, c, 1.0))
    report = check(trajectory, Waypoints(paddle, [a, b, c], via_tolerance=1e-3))
    via = report["via point 1"]
    times = np.linspace(0.0, 2.0, 200_001)
    brute = np.max(np.abs(trajectory.sample(times).q - b), axis=1).min()
    assert not via.ok
    assert brute - 1e-6 <= via.value <= brute + 1e-12
    assert via.value > 5e-3
    assert report.passed("start state", "end state", "velocity")


def test_a_via_point_passed_away_from_the_closest_sample_is_found(paddle):
    # J2 rests at every breakpoint (0, 0.4, 0.35, 0.6, 0.55 rad), the only samples at 0.25 Hz,
    # and passes its via point 0.2 rad mid-way through the first segment, fast: the samples,
    # where J2 is still, say nothing of how fast the distance changes between them.
    def at(j2: float) -> np.ndarray:
        q = Q0.copy()
        q[1] = j2
        return q

    path = [0.0, 0.4, 0.35, 0.6, 0.55]
    pieces = [quintic(at(a), at(b), 1.0) for a, b in pairwise(path)]
    trajectory = pieces[0].then(pieces[1]).then(pieces[2]).then(pieces[3])
    problem = Waypoints(paddle, [at(0.0), at(0.2), at(0.55)], via_tolerance=1e-6)
    found = check(trajectory, problem, rate=0.25)["via point 1"]
    assert found.ok and found.value < 1e-9
    assert found.time == pytest.approx(0.5, abs=1e-9)  # the quintic's middle
