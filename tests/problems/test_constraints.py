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


def test_strike_entry_point_is_run_up_behind_the_contact():
    direction = np.array([0.6, 0.8, 0.0])
    timed = StrikeLine("strike", np.ones(3), direction, 1.5, 0.1, 0.15)
    np.testing.assert_allclose(timed.entry_point, np.ones(3) - 0.15 * direction, atol=1e-15)
    given = dataclasses.replace(timed, run_up=0.2)
    np.testing.assert_allclose(given.entry_point, np.ones(3) - 0.2 * direction, atol=1e-15)
