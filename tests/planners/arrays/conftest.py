"""Fixtures of the array-profile tests: the Robotics Toolbox, when it is installed."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def rtb():
    """The Robotics Toolbox's trajectory module (the ``peers`` extra); skips when absent."""
    return pytest.importorskip(
        "roboticstoolbox.tools.trajectory",
        reason="the Robotics Toolbox is not installed",
        exc_type=ImportError,
    )
