"""Rotation helpers for the tool constraints: angles between axes, rotation log and exp.

Each is accurate near 0 and near pi (angles from ``atan2`` of sine and cosine).

Example::

    turn = rotation_log(R0.T @ R1)                              # (3,) [rad]
    reference = R0[None] @ rotation_exp(s[:, None] * turn[None])  # SLERP at fractions s
    off = rotation_angle(np.swapaxes(reference, 1, 2) @ R)        # (m,) [rad]
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["angle_between", "rotation_angle", "rotation_exp", "rotation_log"]

FloatArray = NDArray[np.float64]


def angle_between(a: FloatArray, b: FloatArray) -> FloatArray:
    """Angles between rows of unit vectors, shape (m,) [rad] (accurate near 0 and pi)."""
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.arctan2(cross, np.sum(a * b, axis=-1))


def rotation_angle(R: FloatArray) -> FloatArray:
    """Rotation angles of rotation matrices, shape (...,) [rad] (accurate near 0 and pi)."""
    w = np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]],
        axis=-1,
    )
    sine = 0.5 * np.linalg.norm(w, axis=-1)
    cosine = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0)
    return np.arctan2(sine, cosine)


def rotation_log(R: FloatArray) -> FloatArray:
    """Rotation vector (axis x angle) of one rotation matrix, shape (3,) [rad]."""
    angle = float(rotation_angle(R))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < np.pi - 1e-6:
        return angle * w / (2.0 * math.sin(angle))
    # Near pi: the axis from the symmetric part, its sign from the skew part.
    B = 0.5 * (R + np.eye(3))
    column = int(np.argmax(np.diag(B)))
    axis = B[:, column] / math.sqrt(max(B[column, column], 1e-300))
    if float(np.dot(axis, w)) < 0.0:
        axis = -axis
    return angle * axis / np.linalg.norm(axis)


def rotation_exp(vectors: FloatArray) -> FloatArray:
    """Rotation matrices of rotation vectors, (m, 3) -> (m, 3, 3) (Rodrigues)."""
    angle = np.linalg.norm(vectors, axis=-1)
    safe = np.where(angle > 1e-12, angle, 1.0)
    axis = vectors / safe[:, None]
    K = np.zeros((len(vectors), 3, 3))
    K[:, 0, 1], K[:, 0, 2] = -axis[:, 2], axis[:, 1]
    K[:, 1, 0], K[:, 1, 2] = axis[:, 2], -axis[:, 0]
    K[:, 2, 0], K[:, 2, 1] = -axis[:, 1], axis[:, 0]
    s = np.where(angle > 1e-12, np.sin(angle), 0.0)[:, None, None]
    c = np.where(angle > 1e-12, 1.0 - np.cos(angle), 0.0)[:, None, None]
    return np.eye(3)[None] + s * K + c * (K @ K)
