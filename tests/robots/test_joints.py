from __future__ import annotations

from collections.abc import Callable

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

from optraj.errors import UnsupportedModelError
from optraj.robots.joints import SUPPORTED_JOINTS, joint_transform, read_joints


def _chain(*joints: tuple[pin.JointModel, pin.SE3]) -> pin.Model:
    model = pin.Model()
    parent = 0
    for k, (joint, placement) in enumerate(joints):
        parent = model.addJoint(parent, joint, placement, f"j{k}")
    return model


def test_read_joints_gives_kinds_axes_and_indices() -> None:
    placement = pin.SE3(np.eye(3), np.array([0.1, 0.2, 0.3]))
    model = _chain(
        (pin.JointModelRY(), pin.SE3.Identity()),
        (pin.JointModelPZ(), placement),
        (pin.JointModelRevoluteUnaligned(0.0, 0.6, 0.8), pin.SE3.Identity()),
    )
    joints = read_joints(model)
    assert [j.kind for j in joints] == ["revolute", "prismatic", "revolute"]
    assert [j.parent for j in joints] == [0, 1, 2]
    assert [j.idx_q for j in joints] == [0, 1, 2]
    np.testing.assert_array_equal(joints[0].axis, [0.0, 1.0, 0.0])
    np.testing.assert_allclose(joints[2].axis, [0.0, 0.6, 0.8])
    np.testing.assert_array_equal(joints[1].translation, [0.1, 0.2, 0.3])


@pytest.mark.parametrize(
    "joint_factory",
    [pin.JointModelSpherical, pin.JointModelFreeFlyer, pin.JointModelRUBX],
    ids=["spherical", "free_flyer", "continuous"],
)
def test_read_joints_rejects_other_types(joint_factory: Callable[[], pin.JointModel]) -> None:
    model = _chain((pin.JointModelRZ(), pin.SE3.Identity()), (joint_factory(), pin.SE3.Identity()))
    with pytest.raises(UnsupportedModelError, match="j1") as info:
        read_joints(model)
    assert all(name in str(info.value) for name in SUPPORTED_JOINTS)


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_joint_transform_matches_pinocchio(kind: str) -> None:
    rotation = pin.utils.rpyToMatrix(0.3, -0.2, 0.5)
    placement = pin.SE3(rotation, np.array([0.1, -0.2, 0.3]))
    joint_model = pin.JointModelRX() if kind == "revolute" else pin.JointModelPY()
    model = _chain((joint_model, placement))
    joint = read_joints(model)[0]
    q = ca.SX.sym("q", 1)
    local = joint_transform(joint, q)
    f = ca.Function("f", [q], [local.rot, local.trans])
    data = model.createData()
    value = np.array([0.7])
    pin.forwardKinematics(model, data, value)
    rot, trans = (np.array(x.full()) for x in f(value))
    np.testing.assert_allclose(rot, data.oMi[1].rotation, atol=1e-12)
    np.testing.assert_allclose(trans.ravel(), data.oMi[1].translation, atol=1e-12)
