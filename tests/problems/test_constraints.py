"""Tests of problems.constraints: plain data, frozen, with the documented strike defaults."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj.problems.constraints import StrikeLine, ToolContact


def test_strike_defaults_are_tighter_than_a_half_degree_shot_needs():
    line = StrikeLine("strike", np.zeros(3), np.array([1.0, 0, 0]), 1.0, 0.1, 0.15)
    assert line.position_tolerance == 1e-5  # 0.01 mm, vs 0.3 mm for a 0.5 deg shot
    assert line.speed_tolerance == 1e-3
    assert np.degrees(line.angle_tolerance) == pytest.approx(0.01)


def test_constraints_are_frozen():
    contact = ToolContact(position=np.zeros(3), time=1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        contact.time = 2.0  # type: ignore[misc]
