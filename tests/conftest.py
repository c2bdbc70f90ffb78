"""Shared fixtures: robots are loaded once per test session (loading Panda takes ~0.6 s)."""

from __future__ import annotations

import importlib.util

import pytest

import robots

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
