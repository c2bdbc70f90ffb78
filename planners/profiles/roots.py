"""Roots of one polynomial per joint, every joint at once.

Closed forms up to degree 3 (the quadratic formula in its cancellation-free form, Cardano's
and the trigonometric formula for cubics) and the eigenvalues of stacked companion matrices
above (what ``np.roots`` does for one polynomial). Only real parts are returned: the callers
take them as candidate points, where a spurious one costs nothing.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["real_roots"]

FloatArray = NDArray[np.float64]


def _quadratic_roots(c: FloatArray, b: FloatArray, a: FloatArray) -> FloatArray:
    """Roots of a x^2 + b x + c per column (real parts; NaN where there is none), (2, n)."""
    root = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
    q = -0.5 * (b + np.copysign(root, b))
    # a == 0: the root of the line b x + c; q == 0 only with b = c = 0 (a root at 0).
    first = np.where(a == 0.0, -c / b, q / a)
    second = np.where(q == 0.0, 0.0, c / q)
    return np.stack([first, second])


def _cubic_roots(coefficients: FloatArray) -> FloatArray:
    """Roots of a x^3 + b x^2 + c x + d per column (real parts), twice: shape (6, n).

    With x = y - b / (3 a), y^3 + p y + q = 0: Cardano's formula where it has one real root,
    the trigonometric form where it has three (Press et al., *Numerical Recipes*, 3rd ed.,
    2007, sec. 5.6); then a Newton step on the cubic itself. A column whose a is below 1e-6
    of its other coefficients takes its quadratic's roots and two Newton steps instead. The
    roots before and after the steps are both returned (NaN or inf where a step failed).
    """
    d, c, b, a = coefficients
    cubic = np.abs(a) > 1e-6 * np.maximum(np.maximum(np.abs(b), np.abs(c)), np.abs(d))
    everywhere = bool(cubic.all())
    inverse = 1.0 / (a if everywhere else np.where(cubic, a, 1.0))
    third = b * inverse / 3.0
    slope1, slope0 = c * inverse, d * inverse
    p = slope1 - 3.0 * third * third
    half = 0.5 * ((2.0 * third * third - slope1) * third + slope0)
    disc = half * half + (p / 3.0) ** 3
    single = disc > 0.0
    if single.all():  # one real root; the complex pair's real part is -root / 2
        sq = np.sqrt(disc)
        one = np.cbrt(sq - half) - np.cbrt(sq + half)
        depressed = np.stack([one, -0.5 * one, -0.5 * one])
    else:
        radius = np.sqrt(np.maximum(p / -3.0, 0.0))
        cosine = np.clip(-half / np.maximum(radius, 1e-100) ** 3, -1.0, 1.0)
        angle = np.arccos(cosine) / 3.0
        depressed = 2.0 * radius * np.cos(angle - _THIRDS)
        if single.any():
            sq = np.sqrt(np.maximum(disc, 0.0))
            one = np.cbrt(sq - half) - np.cbrt(sq + half)
            depressed = np.where(single, np.stack([one, -0.5 * one, -0.5 * one]), depressed)
    found = depressed - third
    steps = 1
    if not everywhere:
        near = np.vstack([_quadratic_roots(d, c, b), np.full((1, d.size), np.nan)])
        found = np.where(cubic, found, near)
        steps = 2
    roots = found
    for _ in range(steps):  # at a multiple root a step may go astray: both are kept
        value = ((a * roots + b) * roots + c) * roots + d
        roots = roots - value / ((3.0 * a * roots + 2.0 * b) * roots + c)
    return np.concatenate([found, roots])


#: Angles [rad] between the three real roots of the trigonometric form.
_THIRDS = (2.0 * np.pi / 3.0) * np.arange(3.0)[:, None]


def real_roots(coefficients: FloatArray) -> FloatArray:
    """Real parts of the roots of each column (ascending powers), shape (m, n), m >= degree.

    Closed forms up to degree 3 (a cubic without constant terms is x times a quadratic),
    companion eigenvalues above. Where a column has fewer roots (a zero leading coefficient)
    the missing ones may be NaN or inf; a cubic's roots come twice, before and after
    polishing. Call with floating-point warnings off.
    """
    degree = coefficients.shape[0] - 1
    if degree == 1:
        return (-coefficients[0] / coefficients[1])[None]
    if degree == 2:
        return _quadratic_roots(*coefficients)
    if degree == 3:
        if not coefficients[0].any():
            return np.vstack(
                [np.zeros((1, coefficients.shape[1])), _quadratic_roots(*coefficients[1:])]
            )
        return _cubic_roots(coefficients)
    lead = coefficients[-1]
    full = lead != 0.0
    n = coefficients.shape[1]
    roots = np.full((degree, n), np.nan)
    if np.any(full):
        columns = coefficients[:, full]
        companion = np.zeros((columns.shape[1], degree, degree))
        companion[:, 0, :] = -(columns[-2::-1] / columns[-1]).T
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        roots[:, full] = np.linalg.eigvals(companion).real.T
    for j in np.flatnonzero(~full):
        if np.any(coefficients[:, j] != 0.0):
            found = np.roots(coefficients[::-1, j]).real
            roots[: found.size, j] = found
    return roots
