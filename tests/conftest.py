"""Shared fixtures: robots loaded once per session (Panda takes ~0.6 s), a thread race; and
how a run on several workers (``pytest -n auto --dist loadfile``, as ``make test`` runs it)
shares the cores: one BLAS thread per worker, the files of slow tests first."""

from __future__ import annotations

import importlib.util
import os
import sys
import threading
from collections import Counter
from collections.abc import Callable

import pytest

from optraj import robots
from optraj.sweeps.processes import THREAD_VARIABLES

SHIPPED = ("paddle4", "sawyer", "youbot")
EXTERNAL = ("panda", "ur5")
HAVE_ERD = importlib.util.find_spec("example_robot_data") is not None

ALL_ROBOTS = [
    *SHIPPED,
    *(
        pytest.param(name, marks=pytest.mark.skipif(not HAVE_ERD, reason="needs optraj[examples]"))
        for name in EXTERNAL
    ),
]

_CACHE: dict[str, robots.Robot] = {}


def get_robot(name: str) -> robots.Robot:
    """A robot loaded once per session; tests must not modify it."""
    if name not in _CACHE:
        _CACHE[name] = robots.load(name)
    return _CACHE[name]


@pytest.fixture(params=ALL_ROBOTS)
def any_robot(request: pytest.FixtureRequest) -> robots.Robot:
    return get_robot(request.param)


def race(worker: Callable[[int], None], threads: int) -> list[BaseException]:
    """Run ``worker(k)`` in ``threads`` threads switching as often as possible; their errors."""
    errors: list[BaseException] = []

    def run(k: int) -> None:
        try:
            worker(k)
        except BaseException as exc:  # collected for the caller to assert on
            errors.append(exc)

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        pool = [threading.Thread(target=run, args=(k,)) for k in range(threads)]
        for thread in pool:
            thread.start()
        for thread in pool:
            thread.join()
    finally:
        sys.setswitchinterval(interval)
    return errors


@pytest.fixture(scope="session")
def pool_shot():
    """The README's Sawyer pool shot at 1 m/s."""
    from optraj import problems

    return problems.sawyer_pool_shot(speed=1.0)


@pytest.fixture(scope="session")
def pool_plan(pool_shot):
    """Its minimum-time strike planned within 80 % of the limits: room for feedback."""
    import dataclasses

    from optraj import planners

    room = dataclasses.replace(pool_shot, limits=pool_shot.robot.limits.scaled(0.8))
    return planners.OptimalControl("time").plan(room)


def pytest_configure(config: pytest.Config) -> None:
    """On the controller of a run over worker processes, give the workers (and the processes
    they start) one BLAS thread each: the workers already occupy every core. A variable the
    user has set is left as it is."""
    distributed = getattr(config.option, "numprocesses", None)
    if distributed and not hasattr(config, "workerinput"):
        for name in THREAD_VARIABLES:
            os.environ.setdefault(name, "1")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """In a worker process, put the files with the most ``slow`` tests first (a stable sort).

    ``--dist loadfile --no-loadscope-reorder`` hands out whole files in this order, so the
    longest files start at once and the many short ones fill the workers' ends. A run in
    one process keeps the collection order.
    """
    if not hasattr(config, "workerinput"):
        return
    slow = Counter(item.path for item in items if item.get_closest_marker("slow"))
    items.sort(key=lambda item: -slow[item.path])
