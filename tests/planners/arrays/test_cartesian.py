"""Tests of planners.arrays.cartesian: ctraj lines, SLERP, the Toolbox's examples, errors."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.arrays.cartesian import ctraj
from optraj.planners.checker.rotations import rotation_angle


def _pose(position, rotation=None):
    T = np.eye(4)
    T[:3, 3] = position
    if rotation is not None:
        T[:3, :3] = rotation
    return T


def _rx(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def test_documented_examples_pass_the_identity_half_way():
    # The Toolbox's tests: SE3(1, 2, 3) to SE3(-1, -2, -3), and Rx(-pi/2) to Rx(pi/2).
    T0, T1 = _pose([1.0, 2.0, 3.0]), _pose([-1.0, -2.0, -3.0])
    poses = ctraj(T0, T1, 3)
    assert poses.shape == (3, 4, 4)
    np.testing.assert_allclose(poses, [T0, np.eye(4), T1], atol=1e-12)
    np.testing.assert_allclose(ctraj(T0, T1, s=[1.0, 0.0, 0.5]), [T1, T0, np.eye(4)], atol=1e-12)
    R0, R1 = _pose([0.0] * 3, _rx(-np.pi / 2)), _pose([0.0] * 3, _rx(np.pi / 2))
    np.testing.assert_allclose(ctraj(R0, R1, 3), [R0, np.eye(4), R1], atol=1e-12)


def test_random_poses_move_on_the_line_and_turn_about_one_axis():
    rng = np.random.default_rng(36)
    for _ in range(30):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = rng.uniform(0.0, 3.0)
        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        turn = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
        start = _pose(rng.normal(size=3), np.linalg.qr(rng.normal(size=(3, 3)))[0])
        if np.linalg.det(start[:3, :3]) < 0:
            start[:3, :3] *= -1.0
        end = _pose(rng.normal(size=3), start[:3, :3] @ turn)
        s = np.sort(rng.uniform(0.0, 1.0, 9))
        poses = ctraj(start, end, s=s)
        np.testing.assert_allclose(
            poses[:, :3, 3], start[:3, 3] + s[:, None] * (end[:3, 3] - start[:3, 3]), atol=1e-12
        )
        relative = np.swapaxes(poses[:, :3, :3], 1, 2) @ start[:3, :3][None]
        np.testing.assert_allclose(rotation_angle(relative), s * angle, atol=1e-9)
        np.testing.assert_allclose(poses[:, 3], [[0.0, 0.0, 0.0, 1.0]] * 9)


def test_times_give_a_trapezoidal_fraction():
    T0, T1 = _pose([0.0, 0.0, 0.0]), _pose([3.0, 0.0, 0.0])
    poses = ctraj(T0, T1, np.linspace(0.0, 2.0, 7))
    # s = trapezoidal(0, 1, t): blends of T / 3 cruising at 1.5 / T; at t = T / 3, s = 1 / 4.
    fractions = [0.0, 1 / 16, 1 / 4, 1 / 2, 3 / 4, 15 / 16, 1.0]  # 2.25 (t / T)^2 in a blend
    np.testing.assert_allclose(poses[:, 0, 3], 3.0 * np.array(fractions), rtol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "name", "words"),
    [
        ({}, "t", "exactly one of them"),
        ({"t": 5, "s": [0.5]}, "t", "exactly one of them"),
        ({"s": [0.5, 1.5]}, "s", r"s must lie in \[0, 1\], got s\[1\] = 1.5"),
        ({"t": [0.0, 2.0, 1.0]}, "t", "strictly increase"),
        ({"t": 5, "T0": np.ones((4, 4))}, "T0", "rotation matrix"),
        ({"t": 5, "T1": np.eye(3)}, "T1", r"shape \(4, 4\)"),
    ],
)
def test_bad_input_is_refused_naming_it(kwargs, name, words):
    args = {"T0": np.eye(4), "T1": _pose([1.0, 0.0, 0.0]), **kwargs}
    with pytest.raises(InvalidInputError, match=words) as caught:
        ctraj(**args)
    assert caught.value.name == name


@pytest.mark.slow
def test_poses_agree_with_the_robotics_toolbox(rtb):
    from spatialmath import SE3

    rng = np.random.default_rng(9)
    for _ in range(10):
        a, b = SE3.Rand(), SE3.Rand()
        for t in (int(rng.integers(2, 30)), np.linspace(0.0, rng.uniform(0.5, 3.0), 17)):
            theirs = np.array([pose.A for pose in rtb.ctraj(a, b, t)])
            np.testing.assert_allclose(ctraj(a.A, b.A, t), theirs, atol=1e-9)
