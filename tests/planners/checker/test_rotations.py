"""Tests of planners.checker.rotations, against Pinocchio's exp3 and log3."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from optraj.planners.checker.rotations import (
    angle_between,
    rotation_angle,
    rotation_exp,
    rotation_log,
)


def random_vectors(rng: np.random.Generator, count: int, largest: float) -> np.ndarray:
    """Rotation vectors with random axes and angles in (0, largest) [rad]."""
    axes = rng.normal(size=(count, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    return axes * rng.uniform(0.0, largest, count)[:, None]


def test_exp_and_log_match_pinocchio():
    rng = np.random.default_rng(33)
    vectors = random_vectors(rng, 50, np.pi - 1e-3)
    matrices = rotation_exp(vectors)
    for vector, R in zip(vectors, matrices, strict=True):
        np.testing.assert_allclose(R, pin.exp3(vector), atol=1e-12)
        np.testing.assert_allclose(rotation_log(R), pin.log3(R), atol=1e-9)
        np.testing.assert_allclose(rotation_log(R), vector, atol=1e-9)
    np.testing.assert_allclose(
        rotation_angle(matrices), np.linalg.norm(vectors, axis=1), atol=1e-12
    )


@pytest.mark.parametrize("angle", [0.0, 1e-14, 1e-7, np.pi - 1e-9, np.pi])
def test_log_is_accurate_near_zero_and_pi(angle):
    axis = np.array([2.0, -1.0, 2.0]) / 3.0
    R = pin.exp3(angle * axis)
    vector = rotation_log(R)
    assert float(rotation_angle(R)) == pytest.approx(angle, abs=1e-9)
    # Near pi the axis's sign is free: the rotation is the same either way.
    np.testing.assert_allclose(rotation_exp(vector[None])[0], R, atol=1e-9)
    if angle < 1e-12:
        np.testing.assert_array_equal(vector, np.zeros(3))


def test_angle_between_rows_is_accurate_near_zero_and_pi():
    x = np.array([[1.0, 0.0, 0.0]] * 4)
    y = np.array(
        [
            [1.0, 0.0, 0.0],
            [np.cos(1e-9), np.sin(1e-9), 0.0],
            [0.0, 1.0, 0.0],
            [-np.cos(1e-9), np.sin(1e-9), 0.0],
        ]
    )
    np.testing.assert_allclose(
        angle_between(x, y), [0.0, 1e-9, np.pi / 2, np.pi - 1e-9], rtol=1e-12, atol=0.0
    )
