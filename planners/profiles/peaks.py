"""Exact extremes of one polynomial per joint on [0, T], every joint at once.

A polynomial's extremes on an interval lie at its ends or where its derivative vanishes. The
roots of that derivative are found for all joints together: in closed form up to degree 2,
and as the eigenvalues of stacked companion matrices above (what ``np.roots`` does for one
polynomial). Every root's real part, clipped to [0, T], joins the candidates: a point of the
interval never overstates an extreme, so no root needs to be judged real or complex.

Rest to rest, a cubic or quintic time scaling is q0 + (q1 - q0) s(t / T) with a fixed shape s,
whose peaks have closed forms (:data:`REST_PEAKS`, :func:`rest_to_rest_peaks`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "REST_PEAKS",
    "extremes",
    "peak_of",
    "polynomial_peaks",
    "position_range",
    "rate_bounds",
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


def _roots(coefficients: FloatArray) -> FloatArray:
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
        inner = _roots(_derivative(coefficients))
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
    exact extremes. A test
    ``lower - low > margin`` or ``high - upper > margin`` thus has the answer the exact
    extremes give.

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
