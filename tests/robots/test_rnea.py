from __future__ import annotations

import casadi as ca
import numpy as np
import pinocchio as pin

from optraj.robots.joints import read_joints
from optraj.robots.rnea import inertia_times_motion, rnea_expression


def _arm() -> pin.Model:
    model = pin.Model()
    rng = np.random.default_rng(3)
    parent = 0
    for k, joint in enumerate([pin.JointModelRZ(), pin.JointModelPX(), pin.JointModelRY()]):
        placement = pin.SE3(pin.utils.rpyToMatrix(*rng.normal(size=3)), rng.normal(size=3))
        parent = model.addJoint(parent, joint, placement, f"j{k}")
        model.appendBodyToJoint(parent, pin.Inertia.Random(), pin.SE3.Identity())
    model.armature = np.array([0.0, 0.2, 0.1])
    return model


def test_rnea_expression_matches_pinocchio() -> None:
    model = _arm()
    q, v, a = (ca.SX.sym(name, model.nv) for name in "qva")
    tau = rnea_expression(read_joints(model), model.gravity, model.nv, q, v, a)
    f = ca.Function("rnea", [q, v, a], [tau])
    rng = np.random.default_rng(5)
    for _ in range(5):
        qn, vn, an = rng.normal(size=(3, model.nv))
        expected = pin.rnea(model, model.createData(), qn, vn, an)
        np.testing.assert_allclose(np.array(f(qn, vn, an).full()).ravel(), expected, atol=1e-9)


def test_inertia_times_motion_is_the_spatial_inertia_product() -> None:
    model = _arm()
    joint = read_joints(model)[0]
    motion = np.array([0.1, -0.3, 0.2, 0.5, 0.4, -0.6])
    lin, ang = inertia_times_motion(joint, (ca.SX(motion[:3]), ca.SX(motion[3:])))
    expected = model.inertias[1].matrix() @ motion
    got = np.concatenate([np.array(ca.DM(lin)).ravel(), np.array(ca.DM(ang)).ravel()])
    np.testing.assert_allclose(got, expected, atol=1e-12)
