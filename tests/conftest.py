"""Shared fixtures: robots loaded once per session (Panda takes ~0.6 s), a thread race."""

from __future__ import annotations

import importlib.util
import sys
import threading
from collections.abc import Callable

import pytest

from optraj import robots

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
