r"""Cartesian poses between two poses: ``ctraj``, as the Robotics Toolbox calls it.

The tool frame's origin moves on the straight line from T0 to T1 and its orientation turns
about one fixed axis (SLERP, :func:`~optraj.planners.checker.rotations.rotation_exp` of the
fraction of :func:`~optraj.planners.checker.rotations.rotation_log`):

.. math:: p(s) = (1 - s) p_0 + s p_1, \qquad R(s) = R_0 \exp(s \log(R_0^T R_1)),

with the fraction s along the path following a trapezoidal profile in time
(:func:`~optraj.planners.arrays.trapezoidal`), or given directly. The Robotics Toolbox returns
an ``SE3`` sequence; here it is an array of 4x4 matrices.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.arrays.scalar import trapezoidal
from optraj.planners.checker.rotations import rotation_exp, rotation_log
from optraj.validation import as_transform, as_vector

__all__ = ["ctraj"]

FloatArray = NDArray[np.float64]


def _fractions(t: int | ArrayLike | None, s: ArrayLike | None) -> FloatArray:
    """The fractions along the path, from ``t`` (a trapezoidal profile) or ``s`` itself."""
    if (t is None) == (s is None):
        raise InvalidInputError(
            "give t (a number of steps or a time vector [s]) or s (fractions along the "
            "path), exactly one of them",
            name="t",
        )
    if s is None:
        return np.array(trapezoidal(0.0, 1.0, t).q)  # type: ignore[arg-type]  # t is given
    fractions = as_vector(s, "s")
    outside = np.flatnonzero((fractions < 0.0) | (fractions > 1.0))
    if outside.size:
        i = int(outside[0])
        raise InvalidInputError(
            f"s must lie in [0, 1], got s[{i}] = {fractions[i]:.6g}", name="s", value=s
        )
    return fractions


def ctraj(
    T0: ArrayLike, T1: ArrayLike, t: int | ArrayLike | None = None, s: ArrayLike | None = None
) -> FloatArray:
    """Poses on the straight line from T0 to T1, orientation by SLERP.

    Args:
        T0: Start pose, a 4x4 homogeneous transform (positions [m]).
        T1: End pose, a 4x4 homogeneous transform.
        t: An int m >= 2, a number of steps, or a time vector [s] from 0 s or later,
            strictly increasing: the fraction along the path follows ``trapezoidal(0, 1, t)``
            (blends of a third of the time, cruising at 1.5 times the mean speed).
        s: Fractions along the path, each in [0, 1], shape (m,), instead of t.

    Returns:
        The poses, shape (m, 4, 4).

    Raises:
        InvalidInputError: T0 or T1 not a rigid transform, both or neither of t and s, a
            fraction outside [0, 1], or a bad t.
    """
    start = as_transform(T0, "T0")
    end = as_transform(T1, "T1")
    fractions = _fractions(t, s)
    turn = rotation_log(start[:3, :3].T @ end[:3, :3])
    poses = np.zeros((fractions.size, 4, 4))
    poses[:, :3, :3] = start[None, :3, :3] @ rotation_exp(fractions[:, None] * turn[None])
    poses[:, :3, 3] = (1.0 - fractions)[:, None] * start[None, :3, 3] + fractions[:, None] * end[
        None, :3, 3
    ]
    poses[:, 3, 3] = 1.0
    return poses
