from __future__ import annotations

import casadi as ca
import numpy as np
import pinocchio as pin

from optraj.robots.spatial import (
    LocalPlacement,
    add,
    axis_rotation,
    const,
    cross,
    force_act,
    motion_act_inv,
    motion_cross_force,
    motion_cross_motion,
    skew,
    snap,
)

RNG = np.random.default_rng(11)


def _num(x: ca.SX) -> np.ndarray:
    return np.array(ca.DM(x)).ravel()


def _pair(vector: np.ndarray) -> tuple[ca.SX, ca.SX]:
    return const(vector[:3]), const(vector[3:])


def test_cross_skew_and_snap() -> None:
    a, b = RNG.normal(size=(2, 3))
    np.testing.assert_allclose(_num(cross(const(a), const(b))), np.cross(a, b), atol=1e-15)
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b), atol=1e-15)
    np.testing.assert_array_equal(snap([1e-15, -1e-15, 0.5]), [0.0, 0.0, 0.5])


def test_axis_rotation_is_rodrigues() -> None:
    axis = RNG.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = 0.8
    got = np.array(ca.DM(axis_rotation(axis, ca.SX(np.cos(angle)), ca.SX(np.sin(angle)))))
    np.testing.assert_allclose(got, pin.exp3(axis * angle), atol=1e-14)


def test_motion_and_force_actions_match_pinocchio() -> None:
    placement = pin.SE3.Random()
    local = LocalPlacement(
        fixed_rot=const(placement.rotation),
        joint_rot=None,
        rot=const(placement.rotation),
        trans=const(placement.translation),
    )
    m, m2, f = RNG.normal(size=(3, 6))
    inv = motion_act_inv(local, _pair(m))
    expected = placement.actInv(pin.Motion(m)).vector
    np.testing.assert_allclose(np.concatenate([_num(x) for x in inv]), expected, atol=1e-12)
    act = force_act(local, _pair(f))
    expected = placement.act(pin.Force(f)).vector
    np.testing.assert_allclose(np.concatenate([_num(x) for x in act]), expected, atol=1e-12)
    mm = motion_cross_motion(_pair(m), _pair(m2))
    expected = pin.Motion(m).cross(pin.Motion(m2)).vector
    np.testing.assert_allclose(np.concatenate([_num(x) for x in mm]), expected, atol=1e-12)
    mf = motion_cross_force(_pair(m), _pair(f))
    expected = pin.Motion(m).cross(pin.Force(f)).vector
    np.testing.assert_allclose(np.concatenate([_num(x) for x in mf]), expected, atol=1e-12)
    total = add(_pair(m), _pair(m2))
    np.testing.assert_allclose(np.concatenate([_num(x) for x in total]), m + m2, atol=1e-15)
