"""Coefficients of the cubic and quintic that meet given end states in a given time.

A cubic meets positions and velocities at both ends, a quintic also accelerations: the end
conditions are linear in the coefficients and are solved here in closed form, for every
joint at once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["cubic_coefficients", "quintic_coefficients"]

FloatArray = NDArray[np.float64]


def cubic_coefficients(
    q0: ArrayLike, q1: ArrayLike, duration: float, v0: ArrayLike = 0.0, v1: ArrayLike = 0.0
) -> FloatArray:
    """Coefficients of q(t) = c0 + c1 t + c2 t^2 + c3 t^3 meeting (q, qd) at t = 0 and T.

    Args:
        q0: Start positions [rad or m], shape (n,).
        q1: End positions, shape (n,).
        duration: T [s].
        v0: Start velocities [rad/s or m/s], shape (n,) or scalar.
        v1: End velocities, shape (n,) or scalar.

    Returns:
        Shape (4, n), row i multiplying t^i.
    """
    p0, p1 = np.asarray(q0, float), np.asarray(q1, float)
    d0, d1 = _row(v0, p0.shape), _row(v1, p0.shape)
    h = float(duration)
    dp = p1 - p0
    c2 = (3.0 * dp - (2.0 * d0 + d1) * h) / h**2
    c3 = ((d0 + d1) * h - 2.0 * dp) / h**3
    return np.stack([p0, d0, c2, c3])


def _row(value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """``value`` (a scalar or an array) as a float array of ``shape``."""
    if type(value) is np.ndarray and value.shape == shape and value.dtype == np.float64:
        return value
    return np.broadcast_to(np.asarray(value, float), shape)


def quintic_coefficients(
    q0: ArrayLike,
    q1: ArrayLike,
    duration: float,
    v0: ArrayLike = 0.0,
    v1: ArrayLike = 0.0,
    a0: ArrayLike = 0.0,
    a1: ArrayLike = 0.0,
) -> FloatArray:
    """Coefficients of the quintic meeting (q, qd, qdd) at t = 0 and t = T.

    The three end conditions on c3, c4, c5 form a 3x3 linear system in the gaps
    dp = q1 - q0 - v0 T - a0 T^2 / 2, dv = v1 - v0 - a0 T and da = a1 - a0, whose closed-form
    solution is used here (the rest of the 6x6 system gives c0 = q0, c1 = v0, c2 = a0 / 2).

    Returns:
        Shape (6, n), row i multiplying t^i [rad/s^i or m/s^i].
    """
    p0, p1 = np.asarray(q0, float), np.asarray(q1, float)
    d0, d1 = _row(v0, p0.shape), _row(v1, p0.shape)
    b0, b1 = _row(a0, p0.shape), _row(a1, p0.shape)
    h = float(duration)
    coeffs = np.empty((6, *p0.shape))
    coeffs[0], coeffs[1], coeffs[2] = p0, d0, 0.5 * b0
    if b0.any() or b1.any():
        gaps = [p1 - p0 - d0 * h - (0.5 * h * h) * b0, d1 - d0 - h * b0, b1 - b0]
    else:
        gaps = [p1 - p0 - d0 * h, d1 - d0, np.zeros(p0.shape)]
    # (c3, c4, c5) = matrix @ (dp, dv, da), the 3x3 end conditions solved once for all
    h2, h3 = h * h, h * h * h
    matrix = np.array(
        [
            [10.0 / h3, -4.0 / h2, 0.5 / h],
            [-15.0 / (h3 * h), 7.0 / h3, -1.0 / h2],
            [6.0 / (h3 * h2), -3.0 / (h3 * h), 0.5 / h3],
        ]
    )
    coeffs[3:] = (matrix @ np.stack(gaps).reshape(3, -1)).reshape((3, *p0.shape))
    return coeffs
