"""The sweep tests plan with planners that misbehave on purpose, registered per test."""

import pytest
from sweeps_support import register_misbehaving


@pytest.fixture(autouse=True)
def _misbehaving_planners(monkeypatch):
    register_misbehaving(monkeypatch)
