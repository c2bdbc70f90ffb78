"""Planners that misbehave on purpose, registered for pool shots, for the sweep tests.

They live in an importable module (tests/ is on the path) so that spawned worker processes
can unpickle them.
"""

from __future__ import annotations

import itertools
import os
import signal
import time

import numpy as np

from optraj import sweeps
from optraj.planners import registry

#: A small grid that plans in well under a second with ruckig: 8 shots, some refused.
SMALL = sweeps.ShotSet(x=(0.7, 0.8), y=(0.0, 0.2), grid=(2, 2), headings=(0.0,), speeds=(0.3, 0.9))
#: A few paddle4 strikes at different points, angles and speeds, all within its limits.
PADDLE = sweeps.PaddleShotSet(
    x=(0.6, 0.9), y=(-0.2, 0.2), z=(0.2, 0.4), headings=(-20.0, 20.0), speeds=(0.3, 0.8),
    samples=3, seed=5,
)  # fmt: skip


def velocity_ratio(trajectory, limits, start, end, samples=2001):
    """Largest |qd_i| / qd_max_i of ``trajectory`` sampled densely over [start, end] [s]."""
    qd = trajectory.sample(np.linspace(start, end, samples)).qd
    return float(np.max(np.abs(qd) / np.asarray(limits.velocity)))


class Raising:
    """Raises on every shot."""

    def plan(self, problem):
        raise RuntimeError("forced failure")


class Sleeping:
    """Sleeps far past any test's time limit (a Python-level hang)."""

    def plan(self, problem):
        time.sleep(60.0)


class Stuck:
    """Sleeps with the alarm blocked, as a long call inside a C library would."""

    def plan(self, problem):
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
        time.sleep(60.0)


class Slow:
    """Plans with ruckig after a pause, so that a run can be stopped half-way."""

    def __init__(self):
        self.ruckig = registry.make_planner("pool-shot", "ruckig")

    def plan(self, problem):
        time.sleep(0.3)
        return self.ruckig.plan(problem)


_PLANNERS = (
    ("test-raise", Raising),
    ("test-sleep", Sleeping),
    ("test-stuck", Stuck),
    ("test-slow", Slow),
)


def register_misbehaving(monkeypatch):
    """Register the planners above for pool shots, for one test: the registry is a copy that
    ``monkeypatch`` puts back, so no other test sees them."""
    kinds = {kind: dict(registry._REGISTRY[kind]) for kind in registry.KINDS}
    monkeypatch.setattr(registry, "_REGISTRY", kinds)
    for name, factory in _PLANNERS:
        registry.register_planner("pool-shot", name, factory)


#: The columns of wall times, which differ from run to run.
WALL_TIMES = ("plan_time", "contact_search_time", "outcome_time")


def outcome(rows):
    """Rows without their wall times."""
    return [{k: v for k, v in row.items() if k not in WALL_TIMES} for row in rows]


class Dying:
    """Ends its worker process on every shot, as a crash in a C library would."""

    def plan(self, problem):
        os._exit(3)


def _refuse():
    raise RuntimeError("this planner does not load here")


class FailsToLoad:
    """Pickles, but cannot be unpickled in a worker process."""

    def __reduce__(self):
        return (_refuse, ())

    def plan(self, problem):  # pragma: no cover - never reached
        raise AssertionError


class StuckOnOne:
    """Plans with ruckig, but gets stuck (as Stuck) on the shot with ball y = 0 and 0.9 m/s."""

    def __init__(self):
        self.ruckig = registry.make_planner("pool-shot", "ruckig")

    def plan(self, problem):
        if problem.ball[1] == 0.0 and problem.speed == 0.9:
            Stuck().plan(problem)
        return self.ruckig.plan(problem)


#: A made-up grid for the map and plot tests: ball x and y [m], headings [deg], speeds [m/s].
XS, YS, HEADINGS, SPEEDS = (0.7, 0.8, 0.9), (0.0, 0.1), (0.0, 45.0), (0.3, 0.9)


def made_up_value(x, y, heading, speed):
    """A made-up value that differs at every cell, heading and speed."""
    return round(10 * x + y + heading / 100 + speed / 1000, 9)


def grid_rows(max_speed_per_position=False):
    """Rows of the made-up grid: x = 0.9 m has no max_speed and the shots at 0.9 m/s are
    refused (no motion time). ``max_speed_per_position``: one max_speed at each ball
    position (its value at 0.9 m/s), as a real sweep gives."""
    from optraj.sweeps.columns import empty_row

    rows = []
    for x, y, heading, speed in itertools.product(XS, YS, HEADINGS, SPEEDS):
        planned = speed < 0.5
        fastest = made_up_value(x, y, heading, 0.9 if max_speed_per_position else speed)
        rows.append(
            empty_row()
            | {
                "shot_id": f"{x}:{y}:{heading}:{speed}",
                "ball_x": x,
                "ball_y": y,
                "heading": heading,
                "speed": speed,
                "status": "planned" if planned else "refused",
                "motion_time": made_up_value(x, y, heading, speed) if planned else None,
                "max_speed": None if x == 0.9 else fastest,
            }
        )
    return rows


def random_rows(count, seed, refused_every=None):
    """``count`` made-up rows of a random set: ball x in [0.6, 0.9] m, y in [0, 0.3] m,
    heading in [-20, 20] deg, speed in [0.3, 0.9] m/s, drawn with ``seed``; row i planned
    with motion time i [s], except every ``refused_every``-th row from the first, refused."""
    import numpy as np

    from optraj.sweeps.columns import empty_row

    rng = np.random.default_rng(seed)
    rows = []
    for i in range(count):
        refused = refused_every is not None and i % refused_every == 0
        rows.append(
            empty_row()
            | {
                "ball_x": rng.uniform(0.6, 0.9),
                "ball_y": rng.uniform(0.0, 0.3),
                "heading": rng.uniform(-20.0, 20.0),
                "speed": rng.uniform(0.3, 0.9),
                "status": "refused" if refused else "planned",
                "motion_time": None if refused else float(i),
            }
        )
    return rows
