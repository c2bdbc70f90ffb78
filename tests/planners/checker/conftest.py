"""Fixtures of the checker tests: the robots and the pool shot, loaded once per module."""

from __future__ import annotations

import pytest
from conftest import get_robot

from optraj import problems
from optraj.robots import Robot


@pytest.fixture(scope="module")
def paddle() -> Robot:
    return get_robot("paddle4")


@pytest.fixture(scope="module")
def sawyer() -> Robot:
    return get_robot("sawyer")


@pytest.fixture(scope="module")
def pool_shot() -> problems.PoolStrike:
    return problems.sawyer_pool_shot()
