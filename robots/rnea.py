"""Inverse dynamics by the recursive Newton-Euler algorithm on CasADi ``SX`` expressions.

The algorithm runs in local joint frames (Featherstone) in Pinocchio's conventions: the base
acceleration is ``-model.gravity`` and the torque includes the reflected rotor inertia
``armature * a``, exactly like ``pinocchio.rnea``.
"""

from __future__ import annotations

import casadi as ca
import pinocchio as pin

from optraj.robots.joints import Joint, joint_transform
from optraj.robots.spatial import (
    Force,
    LocalPlacement,
    Motion,
    add,
    const,
    cross,
    force_act,
    motion_act_inv,
    motion_cross_force,
    motion_cross_motion,
)

__all__ = ["inertia_times_motion", "rnea_expression"]


def inertia_times_motion(joint: Joint, m: Motion) -> Force:
    """Apply the spatial inertia of a body to a motion (momentum or ``I a``).

    With mass ``mass``, centre of mass ``c`` and rotational inertia ``I_c`` about ``c``:
    ``force = mass (v - c x w)`` and ``torque = I_c w + c x force``.

    Args:
        joint: Joint carrying the body (holds mass, COM and inertia).
        m: Motion ``(v, w)`` in the joint frame.

    Returns:
        Spatial force in the joint frame.
    """
    v, w = m
    com = const(joint.com)
    lin = joint.mass * (v - cross(com, w))
    return lin, const(joint.inertia) @ w + cross(com, lin)


def rnea_expression(
    joints: list[Joint], gravity: pin.Motion, nv: int, q: ca.SX, v: ca.SX, a: ca.SX
) -> ca.SX:
    """RNEA in local joint frames (Featherstone), following Pinocchio's conventions.

    Args:
        joints: The model's joints, in model order.
        gravity: The model's gravity (``model.gravity``).
        nv: Number of joint velocity coordinates.
        q: Joint positions [rad or m], shape (nq, 1).
        v: Joint velocities [rad/s or m/s], shape (nv, 1) (may be numeric zeros).
        a: Joint accelerations [rad/s^2 or m/s^2], shape (nv, 1) (may be numeric zeros).

    Returns:
        Joint torques/forces [N m or N], shape (nv, 1).
    """
    n = len(joints)
    zero = ca.SX.zeros(3, 1)
    base_vel: Motion = (zero, zero)
    base_acc: Motion = (const(-gravity.linear), const(-gravity.angular))

    placements: list[LocalPlacement] = []
    vels: list[Motion] = []
    forces: list[Force] = []
    # Forward pass: velocities, accelerations (gravity folded into the base) and forces.
    accs: list[Motion] = []
    for joint in joints:
        local = joint_transform(joint, q)
        placements.append(local)
        axis = const(joint.axis)
        qd = v[joint.idx_v]
        qdd = a[joint.idx_v]
        if joint.kind == "revolute":
            s_qd: Motion = (zero, axis * qd)
            s_qdd: Motion = (zero, axis * qdd)
        else:
            s_qd = (axis * qd, zero)
            s_qdd = (axis * qdd, zero)
        if joint.parent == 0:
            parent_vel, parent_acc = base_vel, base_acc
        else:
            parent_vel, parent_acc = vels[joint.parent - 1], accs[joint.parent - 1]
        vel = add(motion_act_inv(local, parent_vel), s_qd)
        acc = add(
            add(motion_act_inv(local, parent_acc), s_qdd),
            motion_cross_motion(vel, s_qd),
        )
        vels.append(vel)
        accs.append(acc)
        forces.append(
            add(
                inertia_times_motion(joint, acc),
                motion_cross_force(vel, inertia_times_motion(joint, vel)),
            )
        )

    # Backward pass: project on the motion subspace and propagate to the parent.
    tau: list[ca.SX] = [ca.SX(0.0)] * nv
    for k in range(n - 1, -1, -1):
        joint = joints[k]
        lin, ang = forces[k]
        axis = const(joint.axis)
        projected = ca.dot(axis, ang if joint.kind == "revolute" else lin)
        if joint.armature != 0.0:
            projected = projected + joint.armature * a[joint.idx_v]
        tau[joint.idx_v] = projected
        if joint.parent > 0:
            forces[joint.parent - 1] = add(
                forces[joint.parent - 1], force_act(placements[k], forces[k])
            )
    return ca.vertcat(*tau) if tau else ca.SX.zeros(0, 1)
