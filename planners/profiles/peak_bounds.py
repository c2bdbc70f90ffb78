"""Cheap bounds on the peaks of one polynomial per joint, to spare most exact root solving.

:func:`position_range` bounds positions by Bernstein coefficients on pieces of [0, T] and
solves exactly only where a box may be left; :func:`rate_bounds` brackets the peak rates
between grid values and grid values plus a curvature bound. A check that a limit is kept
thus needs the exact peaks of the few joints near a limit only.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from optraj.planners.profiles.peaks import extremes

__all__ = ["position_range", "rate_bounds"]

FloatArray = NDArray[np.float64]


def _bernstein_matrix(degree: int) -> FloatArray:
    """M such that M @ a holds the Bernstein coefficients on [0, 1] of sum_i a_i x^i.

    The standard change of basis, b_k = sum_{i <= k} C(k, i) / C(d, i) a_i (Farin, *Curves
    and Surfaces for CAGD*, 5th ed., 2002).
    """
    matrix = np.zeros((degree + 1, degree + 1))
    for k in range(degree + 1):
        for i in range(k + 1):
            matrix[k, i] = math.comb(k, i) / math.comb(degree, i)
    return matrix


_BERNSTEIN = {degree: _bernstein_matrix(degree) for degree in range(8)}
#: Pieces of [0, 1] whose Bernstein coefficients :func:`position_range` takes.
_PIECES = 4


def _piecewise_bernstein(degree: int) -> FloatArray:
    """Rows mapping sum_i a_i x^i to its Bernstein coefficients on equal pieces of [0, 1].

    Shape (_PIECES (degree + 1), degree + 1). On the piece [s, s + h], x = s + h u and the
    power coefficients in u are sum_{i >= m} C(i, m) s^(i - m) h^m a_i.
    """
    h = 1.0 / _PIECES
    rows = []
    for piece in range(_PIECES):
        start = piece * h
        shift = np.zeros((degree + 1, degree + 1))
        for m in range(degree + 1):
            for i in range(m, degree + 1):
                shift[m, i] = math.comb(i, m) * start ** (i - m) * h**m
        rows.append(_BERNSTEIN[degree] @ shift)
    return np.concatenate(rows)


_PIECEWISE = {degree: _piecewise_bernstein(degree) for degree in range(8)}


def position_range(
    coefficients: FloatArray, duration: float, lower: FloatArray, upper: FloatArray, margin: float
) -> tuple[FloatArray, FloatArray]:
    """Lowest and highest value on [0, T] of each column, exact where it may leave a box.

    A polynomial lies within the range of its Bernstein coefficients on each of four equal
    pieces of [0, T]; a column whose range is within [lower - margin, upper + margin] gets that
    range (its extremes do not leave the box by more than margin), every other column its
    exact extremes. A test ``lower - low > margin`` or ``high - upper > margin`` thus has the
    answer the exact extremes give.

    Args:
        coefficients: Shape (d + 1, n), row i multiplying t^i.
        duration: T [s].
        lower: Lower bounds, shape (n,).
        upper: Upper bounds, shape (n,).
        margin: Excess tolerated [same unit].
    """
    degree = coefficients.shape[0] - 1
    if degree not in _BERNSTEIN:
        return extremes(coefficients, duration)
    scaled = coefficients * (duration ** np.arange(degree + 1.0))[:, None]
    hull = _PIECEWISE[degree] @ scaled
    low, high = hull.min(axis=0), hull.max(axis=0)
    unsure = (lower - low > margin) | (high - upper > margin)
    if np.any(unsure):
        exact_low, exact_high = extremes(coefficients[:, unsure], duration)
        low[unsure], high[unsure] = exact_low, exact_high
    return low, high


#: Intervals of the grid on which :func:`rate_bounds` samples a polynomial over [0, T].
_INTERVALS = 32
_GRID = np.linspace(0.0, 1.0, _INTERVALS + 1)


def _falling(i: int, order: int) -> float:
    """The factor i (i - 1) ... (i - order + 1) that d^order/dx^order brings down from x^i."""
    return float(math.perm(i, order))


def _screen_matrix(degree: int) -> FloatArray:
    """Rows that map b, the coefficients in normalised time x = t / T, to derivatives.

    First the values of the first three derivatives on the grid, then the Bernstein
    coefficients of the derivatives two orders higher (zero rows where there are none); shape
    (3 (G + degree + 1), degree + 1).
    """
    size = degree + 1
    grid = np.zeros((3, _GRID.size, size))
    hull = np.zeros((3, size, size))
    for k, order in enumerate((1, 2, 3)):
        for i in range(order, size):
            grid[k, :, i] = _falling(i, order) * _GRID ** (i - order)
        higher = order + 2
        if higher <= degree:
            derivative = np.zeros((degree - higher + 1, size))
            for i in range(higher, size):
                derivative[i - higher, i] = _falling(i, higher)
            hull[k, : degree - higher + 1] = (
                _BERNSTEIN.get(degree - higher, np.ones((1, 1))) @ derivative
            )
    return np.concatenate([grid.reshape(-1, size), hull.reshape(-1, size)])


_SCREENS = {degree: _screen_matrix(degree) for degree in (3, 5)}
#: sum_i |b_i| i!/(i - k)!, for k = 1, 2, 3: what bounds the terms of a derivative on [0, 1].
_TERMS = {
    degree: np.array([[_falling(i, k) for i in range(degree + 1)] for k in (1, 2, 3)])
    for degree in (3, 5)
}
#: Relative round-off allowed for in a grid value (the size of its terms times this).
_ROUND_OFF = 1e-12


def rate_bounds(coefficients: FloatArray, duration: float) -> tuple[FloatArray, FloatArray]:
    """Lower and upper bounds on the peak |velocity|, |acceleration| and |jerk| on [0, T].

    The lower bound is the largest value on a grid of spacing h = T / 32; the peak lies at
    most h / 2 from a grid point where the derivative of the function vanishes, so it exceeds
    that grid value by at most (h / 2)^2 / 2 times the largest second derivative, bounded by
    the largest Bernstein coefficient of that second derivative. Both bounds allow for
    round-off, 1e-12 of the size of the terms.

    Args:
        coefficients: Shape (d + 1, n), d = 3 or 5, row i multiplying t^i.
        duration: T [s].

    Returns:
        (lower, upper), each shape (3, n): velocity, acceleration and jerk rows.
    """
    degree = coefficients.shape[0] - 1
    n = coefficients.shape[1]
    normalised = coefficients * (duration ** np.arange(degree + 1.0))[:, None]
    values = np.abs(_SCREENS[degree] @ normalised)
    cut = 3 * _GRID.size
    lower = values[:cut].reshape(3, _GRID.size, n).max(axis=1)
    curvature = values[cut:].reshape(3, degree + 1, n).max(axis=1)
    scale = (duration ** -np.arange(1.0, 4.0))[:, None]
    margin = 0.125 / _INTERVALS**2
    terms = _TERMS[degree] @ np.abs(normalised)
    rounding = _ROUND_OFF * terms
    return (lower - rounding) * scale, (lower + margin * curvature + rounding) * scale
