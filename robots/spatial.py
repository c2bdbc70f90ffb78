"""Spatial algebra on CasADi ``SX`` expressions, in Pinocchio's conventions.

Spatial motion vectors are ``(linear, angular)`` pairs and spatial forces ``(force, torque)``
pairs, each component an ``SX`` of shape (3, 1). A placement maps child coordinates into parent
coordinates: ``x_parent = R @ x_child + p``.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import numpy.typing as npt

__all__ = [
    "SNAP_TOL",
    "Force",
    "LocalPlacement",
    "Motion",
    "add",
    "axis_rotation",
    "const",
    "cross",
    "force_act",
    "motion_act_inv",
    "motion_cross_force",
    "motion_cross_motion",
    "skew",
    "snap",
]

FloatArray = npt.NDArray[np.float64]
Motion = tuple[ca.SX, ca.SX]
"""Spatial motion vector as ``(linear, angular)``, each an ``SX`` of shape (3, 1)."""
Force = tuple[ca.SX, ca.SX]
"""Spatial force vector as ``(force, torque)``, each an ``SX`` of shape (3, 1)."""

#: Entries below this magnitude read from a model are round-off and become exact zeros.
SNAP_TOL = 1e-14


@dataclass
class LocalPlacement:
    """Placement of a joint frame in its parent joint frame, ``jointPlacements[i] * M_joint(q)``.

    The rotation is available both factored (``fixed_rot @ joint_rot``, cheaper when chaining
    world rotations) and multiplied out once (``rot``, cheaper when the same rotation is
    applied to many vectors as in the RNEA).

    Attributes:
        fixed_rot: Constant rotation of the joint placement [-], shape (3, 3).
        joint_rot: Rotation about the joint axis [-], shape (3, 3), or ``None`` (prismatic).
        rot: ``fixed_rot @ joint_rot`` [-], shape (3, 3).
        trans: Joint origin in the parent frame [m], shape (3, 1).
    """

    fixed_rot: ca.SX
    joint_rot: ca.SX | None
    rot: ca.SX
    trans: ca.SX

    def rotate(self, x: ca.SX) -> ca.SX:
        """Rotate a child-frame vector into the parent frame, shape (3, 1) -> (3, 1)."""
        return self.rot @ x

    def rotate_inv(self, x: ca.SX) -> ca.SX:
        """Rotate a parent-frame vector into the child frame, shape (3, 1) -> (3, 1)."""
        return self.rot.T @ x


def const(values: npt.ArrayLike) -> ca.SX:
    """Wrap a numeric array as a dense SX constant (zeros stay as explicit constants).

    Args:
        values: Numeric vector or matrix.

    Returns:
        Dense SX constant with the same shape (vectors become columns).
    """
    return ca.SX(ca.DM(np.asarray(values, dtype=float)))


def snap(values: npt.ArrayLike) -> FloatArray:
    """Replace round-off noise (e.g. ``cos(pi/2)`` from URDF ``rpy``) by exact zeros.

    Exact zeros let CasADi drop the corresponding products, which keeps graphs compact; the
    change is below 1e-14 and thus far beneath any meaningful tolerance.

    Args:
        values: Numeric array read from the Pinocchio model.

    Returns:
        Float copy with entries of magnitude below 1e-14 set to 0.
    """
    out = np.array(values, dtype=float)
    out[np.abs(out) < SNAP_TOL] = 0.0
    return out


def cross(a: ca.SX, b: ca.SX) -> ca.SX:
    """Cross product of two 3-vectors.

    Args:
        a: First vector, shape (3, 1).
        b: Second vector, shape (3, 1).

    Returns:
        ``a x b``, shape (3, 1).
    """
    return ca.vertcat(
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def skew(w: npt.ArrayLike) -> FloatArray:
    """Numeric skew-symmetric matrix such that ``skew(w) @ x == w x x``.

    Args:
        w: Vector, shape (3,).

    Returns:
        Skew-symmetric matrix, shape (3, 3).
    """
    x, y, z = np.asarray(w, dtype=float)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def axis_rotation(axis: FloatArray, cos_q: ca.SX, sin_q: ca.SX) -> ca.SX:
    """Rotation matrix about a constant unit axis (Rodrigues), assembled entry by entry.

    Each entry is ``(delta_ij - a_i a_j) cos + skew(a)_ij sin + a_i a_j``; terms whose numeric
    coefficient vanishes are dropped so aligned axes give the familiar sparse matrices.

    Args:
        axis: Unit rotation axis [-], shape (3,).
        cos_q: Cosine of the joint angle.
        sin_q: Sine of the joint angle.

    Returns:
        Rotation matrix, shape (3, 3).
    """
    outer = np.outer(axis, axis)
    cos_coeff = np.eye(3) - outer
    sin_coeff = skew(axis)
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            entry = ca.SX(float(outer[i, j]))
            if cos_coeff[i, j] != 0.0:
                entry = entry + float(cos_coeff[i, j]) * cos_q
            if sin_coeff[i, j] != 0.0:
                entry = entry + float(sin_coeff[i, j]) * sin_q
            row.append(entry)
        rows.append(ca.horzcat(*row))
    return ca.vertcat(*rows)


def motion_act_inv(placement: LocalPlacement, m: Motion) -> Motion:
    """Express a motion given in parent coordinates in child coordinates (``M.actInv``).

    Args:
        placement: Placement of the child frame in the parent frame.
        m: Motion ``(linear, angular)`` in parent coordinates.

    Returns:
        The same motion in child coordinates.
    """
    lin, ang = m
    return placement.rotate_inv(lin - cross(placement.trans, ang)), placement.rotate_inv(ang)


def force_act(placement: LocalPlacement, f: Force) -> Force:
    """Express a force given in child coordinates in parent coordinates (``M.act``).

    Args:
        placement: Placement of the child frame in the parent frame.
        f: Force ``(force, torque)`` in child coordinates.

    Returns:
        The same force in parent coordinates.
    """
    lin = placement.rotate(f[0])
    return lin, placement.rotate(f[1]) + cross(placement.trans, lin)


def motion_cross_motion(m1: Motion, m2: Motion) -> Motion:
    """Spatial cross product of two motions, ``m1 x m2``.

    Args:
        m1: Motion ``(v1, w1)``.
        m2: Motion ``(v2, w2)``.

    Returns:
        ``(w1 x v2 + v1 x w2, w1 x w2)``.
    """
    v1, w1 = m1
    v2, w2 = m2
    return cross(w1, v2) + cross(v1, w2), cross(w1, w2)


def motion_cross_force(m: Motion, f: Force) -> Force:
    """Dual spatial cross product of a motion and a force, ``m x* f``.

    Args:
        m: Motion ``(v, w)``.
        f: Force ``(force, torque)``.

    Returns:
        ``(w x force, w x torque + v x force)``.
    """
    v, w = m
    lin, ang = f
    return cross(w, lin), cross(w, ang) + cross(v, lin)


def add(a: tuple[ca.SX, ca.SX], b: tuple[ca.SX, ca.SX]) -> tuple[ca.SX, ca.SX]:
    """Add two spatial vectors of the same kind component by component.

    Args:
        a: First spatial vector.
        b: Second spatial vector.

    Returns:
        Component-wise sum.
    """
    return a[0] + b[0], a[1] + b[1]
