"""The joints of a Pinocchio model that the symbolic model supports, read once as constants.

Only single-DOF revolute and prismatic joints (aligned with an axis of the joint frame or along
an arbitrary constant axis) are supported; :func:`read_joints` rejects every other type.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import casadi as ca
import numpy as np
import numpy.typing as npt
import pinocchio as pin

from optraj.errors import UnsupportedModelError
from optraj.robots.spatial import LocalPlacement, axis_rotation, const, snap

__all__ = ["SUPPORTED_JOINTS", "Joint", "joint_transform", "read_joints"]

FloatArray = npt.NDArray[np.float64]

REVOLUTE_AXES: dict[str, tuple[float, float, float]] = {
    "JointModelRX": (1.0, 0.0, 0.0),
    "JointModelRY": (0.0, 1.0, 0.0),
    "JointModelRZ": (0.0, 0.0, 1.0),
}
PRISMATIC_AXES: dict[str, tuple[float, float, float]] = {
    "JointModelPX": (1.0, 0.0, 0.0),
    "JointModelPY": (0.0, 1.0, 0.0),
    "JointModelPZ": (0.0, 0.0, 1.0),
}
REVOLUTE_UNALIGNED = "JointModelRevoluteUnaligned"
PRISMATIC_UNALIGNED = "JointModelPrismaticUnaligned"
#: Pinocchio joint type names the symbolic model supports.
SUPPORTED_JOINTS = (
    *REVOLUTE_AXES,
    *PRISMATIC_AXES,
    REVOLUTE_UNALIGNED,
    PRISMATIC_UNALIGNED,
)


@dataclass(frozen=True)
class Joint:
    """Constant description of one supported joint, read once from the Pinocchio model.

    Attributes:
        index: Joint index in the Pinocchio model (>= 1).
        parent: Index of the parent joint (0 is the universe).
        kind: ``"revolute"`` or ``"prismatic"``.
        axis: Unit joint axis in the joint frame [-], shape (3,).
        idx_q: Index of the joint coordinate in ``q``.
        idx_v: Index of the joint velocity in ``v``.
        rotation: Rotation of the joint placement w.r.t. the parent joint [-], shape (3, 3).
        translation: Translation of the joint placement w.r.t. the parent joint [m], shape (3,).
        mass: Body mass [kg].
        com: Body centre of mass in the joint frame [m], shape (3,).
        inertia: Rotational inertia about the centre of mass [kg m^2], shape (3, 3).
        armature: Reflected rotor inertia added to the joint torque [kg m^2 or kg].
    """

    index: int
    parent: int
    kind: Literal["revolute", "prismatic"]
    axis: FloatArray
    idx_q: int
    idx_v: int
    rotation: FloatArray
    translation: FloatArray
    mass: float
    com: FloatArray
    inertia: FloatArray
    armature: float


def joint_transform(joint: Joint, q: ca.SX) -> LocalPlacement:
    """Placement of a joint frame in its parent joint frame at position ``q``.

    Args:
        joint: Joint description.
        q: Full joint-position vector [rad or m], shape (nq, 1).

    Returns:
        ``jointPlacements[i] * joint_motion(q_i)`` in factored form.
    """
    q_i = q[joint.idx_q]
    fixed_rot = const(joint.rotation)
    trans = const(joint.translation)
    if joint.kind == "revolute":
        joint_rot = axis_rotation(joint.axis, ca.cos(q_i), ca.sin(q_i))
        return LocalPlacement(
            fixed_rot=fixed_rot, joint_rot=joint_rot, rot=fixed_rot @ joint_rot, trans=trans
        )
    shift = const(snap(joint.rotation @ joint.axis)) * q_i
    return LocalPlacement(fixed_rot=fixed_rot, joint_rot=None, rot=fixed_rot, trans=trans + shift)


def read_joints(model: pin.Model) -> list[Joint]:
    """Read and validate the joints of a Pinocchio model.

    Args:
        model: Pinocchio model.

    Returns:
        One :class:`Joint` per joint, universe excluded, in model order.

    Raises:
        UnsupportedModelError: If a joint type is not a supported 1-DOF revolute/prismatic.
    """
    joints: list[Joint] = []
    for index in range(1, model.njoints):
        jmodel = model.joints[index]
        jtype = jmodel.shortname()
        name = model.names[index]
        if jtype not in SUPPORTED_JOINTS or jmodel.nq != 1 or jmodel.nv != 1:
            raise UnsupportedModelError(
                f"Joint {name!r} (index {index}) of model {model.name!r} has type {jtype}, "
                f"which SymbolicModel does not support. Supported joint types: "
                f"{', '.join(SUPPORTED_JOINTS)}."
            )
        kind: Literal["revolute", "prismatic"]
        if jtype in REVOLUTE_AXES:
            kind, axis = "revolute", np.array(REVOLUTE_AXES[jtype])
        elif jtype in PRISMATIC_AXES:
            kind, axis = "prismatic", np.array(PRISMATIC_AXES[jtype])
        else:
            kind = "revolute" if jtype == REVOLUTE_UNALIGNED else "prismatic"
            axis = np.array(jmodel.extract().axis, dtype=float).reshape(3)
        placement = model.jointPlacements[index]
        inertia = model.inertias[index]
        joints.append(
            Joint(
                index=index,
                parent=int(model.parents[index]),
                kind=kind,
                axis=axis,
                idx_q=int(jmodel.idx_q),
                idx_v=int(jmodel.idx_v),
                rotation=snap(placement.rotation),
                translation=snap(placement.translation).reshape(3),
                mass=float(inertia.mass),
                com=snap(inertia.lever).reshape(3),
                inertia=snap(inertia.inertia),
                armature=float(model.armature[jmodel.idx_v]),
            )
        )
    return joints
