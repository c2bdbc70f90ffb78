"""Exact extremes of one polynomial per joint on [0, T], every joint at once.

A polynomial's extremes on an interval lie at its ends or where its derivative vanishes. The
roots of that derivative are found for all joints together (:mod:`.roots`). Every root's real
part, clipped to [0, T], joins the candidates: a point of the interval never overstates an
extreme, so no root needs to be judged real or complex. Bounds that spare most of this work
are in :mod:`.peak_bounds`.

Rest to rest, a cubic or quintic time scaling is q0 + (q1 - q0) s(t / T) with a fixed shape s,
whose peaks have closed forms (:data:`REST_PEAKS`, :func:`rest_to_rest_peaks`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.planners.profiles.roots import real_roots

__all__ = [
    "REST_PEAKS",
    "extremes",
    "peak_of",
    "polynomial_peaks",
    "rate_peaks",
    "rest_to_rest_peaks",
]

FloatArray = NDArray[np.float64]

#: Peaks of |s'|, |s''| and |s'''| on [0, 1] of the rest-to-rest shapes, by polynomial degree.
#: Cubic, s = 3x^2 - 2x^3: s' = 6x(1 - x) peaks at x = 1/2 (3/2); s'' = 6 - 12x at the ends
#: (6); s''' = -12. Quintic, s = 10x^3 - 15x^4 + 6x^5: s' = 30x^2(1 - x)^2 peaks at x = 1/2
#: (15/8); s'' = 60x(1 - x)(1 - 2x) where s''' = 0, x = (3 -+ sqrt 3)/6, giving 10/sqrt(3);
#: s''' = 60 - 360x + 360x^2 at the ends (60, against -30 at x = 1/2). Our derivation; the
#: same values are tabled by Biagiotti & Melchiorri, *Trajectory Planning for Automatic
#: Machines and Robots*, Springer 2008, ch. 2.
REST_PEAKS: dict[int, tuple[float, float, float]] = {
    3: (1.5, 6.0, 12.0),
    5: (1.875, 10.0 / math.sqrt(3.0), 60.0),
}


def rest_to_rest_peaks(
    q0: FloatArray, q1: FloatArray, duration: float, degree: int
) -> dict[str, FloatArray]:
    """Peaks of the rest-to-rest cubic (degree 3) or quintic (5) from q0 to q1 in T [s].

    The k-th derivative is (q1 - q0) s^(k)(t / T) / T^k, so its peak is the shape's
    (:data:`REST_PEAKS`) times |q1 - q0| / T^k; the motion is monotone, so the positions stay
    between q0 and q1.

    Returns:
        As :func:`polynomial_peaks`.
    """
    velocity, acceleration, jerk = REST_PEAKS[degree]
    distance = np.abs(q1 - q0)
    return {
        "position_min": np.minimum(q0, q1),
        "position_max": np.maximum(q0, q1),
        "velocity": distance * (velocity / duration),
        "acceleration": distance * (acceleration / duration**2),
        "jerk": distance * (jerk / duration**3),
    }


def _derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients (ascending powers, one column per joint) of the derivative."""
    degree = coefficients.shape[0] - 1
    if degree == 0:
        return np.zeros_like(coefficients)
    return coefficients[1:] * np.arange(1.0, degree + 1.0)[:, None]


def extremes(coefficients: FloatArray, duration: float) -> tuple[FloatArray, FloatArray]:
    """Smallest and largest value on [0, T] [s] of each column (ascending powers), shapes (n,).

    Exact: the values at both ends and wherever the derivative vanishes (each column's
    polynomial at its own candidate times, by Horner's scheme).
    """
    degree = coefficients.shape[0] - 1
    start = coefficients[0]
    end = (duration ** np.arange(degree + 1.0)) @ coefficients
    low, high = np.minimum(start, end), np.maximum(start, end)
    if degree < 2:  # constant or linear: its ends
        return low, high
    with np.errstate(all="ignore"):
        inner = real_roots(_derivative(coefficients))
    times = np.fmin(np.fmax(inner, 0.0), duration)  # NaN to 0, beyond the ends to the ends
    values = coefficients[-1] * times + coefficients[-2]
    for row in coefficients[-3::-1]:
        values = values * times + row
    return np.minimum(low, values.min(axis=0)), np.maximum(high, values.max(axis=0))


def _abs_peak(coefficients: FloatArray, duration: float) -> FloatArray:
    low, high = extremes(coefficients, duration)
    return np.maximum(high, -low)


def polynomial_peaks(coefficients: ArrayLike, duration: float) -> dict[str, FloatArray]:
    """Exact peak |velocity|, |acceleration| and |jerk| of one polynomial per joint on [0, T].

    Args:
        coefficients: Shape (d + 1, n), row i multiplying t^i.
        duration: T [s].

    Returns:
        ``{"position_min", "position_max", "velocity", "acceleration", "jerk"}``, each shape
        (n,) (absolute peaks for the derivatives).
    """
    coeffs = np.asarray(coefficients, float)
    velocity = _derivative(coeffs)
    acceleration = _derivative(velocity)
    jerk = _derivative(acceleration)
    low, high = extremes(coeffs, duration)
    return {
        "position_min": low,
        "position_max": high,
        "velocity": _abs_peak(velocity, duration),
        "acceleration": _abs_peak(acceleration, duration),
        "jerk": _abs_peak(jerk, duration),
    }


def peak_of(quantity: str, coefficients: FloatArray, duration: float) -> FloatArray:
    """Exact peak on [0, T] of |velocity|, |acceleration| or |jerk| (``quantity``), (n,)."""
    order = {"velocity": 1, "acceleration": 2, "jerk": 3}[quantity]
    derivative = coefficients
    for _ in range(order):
        derivative = _derivative(derivative)
    return _abs_peak(derivative, duration)


def rate_peaks(coefficients: FloatArray, duration: float) -> dict[str, FloatArray]:
    """Exact peak |velocity|, |acceleration| and |jerk| on [0, T] per column, shapes (n,)."""
    velocity = _derivative(coefficients)
    acceleration = _derivative(velocity)
    return {
        "velocity": _abs_peak(velocity, duration),
        "acceleration": _abs_peak(acceleration, duration),
        "jerk": _abs_peak(_derivative(acceleration), duration),
    }
