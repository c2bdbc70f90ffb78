"""Helpers of the via-point tests (via_lspb, via_quintic), as fixtures that return them."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from optraj import problems


def _random_waypoints(rng, robot, **kwargs):
    """Random limits and 2..8 waypoints, some repeated, some joints not moving at all."""
    n = robot.dof
    limits = dataclasses.replace(
        robot.limits, velocity=rng.uniform(0.3, 5.0, n), acceleration=rng.uniform(1.0, 40.0, n)
    )
    k = int(rng.integers(2, 9))
    points = limits.sample(rng, k)
    if rng.random() < 0.2:
        points[rng.integers(1, k)] = points[rng.integers(0, k)]
    if rng.random() < 0.3:
        j = rng.integers(0, n)
        points[:, j] = points[0, j]
    if not np.any(points != points[0]):
        points[-1] = limits.sample(rng, 1)[0]
    return problems.Waypoints(robot, points, limits=limits, **kwargs)


def _sides(traj, order_max):
    """Derivatives 0..order_max just left and right of every inner breakpoint, exactly."""
    knots = traj.breakpoints
    lengths = np.diff(knots)[:-1]
    out = []
    c = traj.coefficients
    for _ in range(order_max + 1):
        powers = lengths[:, None] ** np.arange(c.shape[1])[None, :]
        out.append((np.einsum("kd,kdn->kn", powers, c[:-1]), c[1:, 0]))
        c = c[:, 1:] * np.arange(1, c.shape[1])[None, :, None]
    return out


def _at_rest_on_the_ends(traj, points):
    first, last = traj.sample(0.0), traj.sample(traj.duration)
    np.testing.assert_array_equal(first.q, points[0])
    np.testing.assert_allclose(last.q, points[-1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(first.qd, 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(last.qd, 0.0, rtol=0, atol=1e-12)


def _within_limits(traj, limits, rate):
    sample = traj.sample(traj.times(rate))
    assert np.all(np.abs(sample.qd) <= limits.velocity * (1 + 1e-9))
    assert np.all(np.abs(sample.qdd) <= limits.acceleration * (1 + 1e-9))
    assert np.all(limits.contains(sample.q, tolerance=1e-12))


@pytest.fixture
def via() -> SimpleNamespace:
    """The helpers: ``random_waypoints(rng, robot, **kwargs)``, ``sides(traj, order_max)``,
    ``at_rest_on_the_ends(traj, points)`` and ``within_limits(traj, limits, rate)``."""
    return SimpleNamespace(
        random_waypoints=_random_waypoints,
        sides=_sides,
        at_rest_on_the_ends=_at_rest_on_the_ends,
        within_limits=_within_limits,
    )
