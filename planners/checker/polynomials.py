"""Piecewise polynomials, exactly: derivatives, evaluation, real roots and extreme candidates.

A trajectory's joint motion is a piecewise polynomial, coefficients of shape (K, d + 1, n)
in ascending powers of the local time of each of K segments between the breakpoints
``knots`` (K + 1,). :func:`derivatives_of` differentiates it, :func:`evaluate_piecewise`
samples it, and :func:`exact_candidates` finds the instants where a joint quantity can take
its worst value on every segment (Bernstein enclosures rule segments out, real roots of the
derivative rule the rest in), so a maximum over them is the exact maximum.

Example::

    table = derivatives_of(trajectory.coefficients, 3)
    qd = evaluate_piecewise(table[1], knots, times)          # (m, n)
    found = exact_candidates(knots, table[1], lambda x, j: np.abs(x), math.inf)
    peak = np.max(np.abs(found.value))                      # exact peak speed
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.allowance import round_off

__all__ = [
    "Candidates",
    "Score",
    "bernstein",
    "critical_points",
    "derivatives_of",
    "evaluate_piecewise",
    "exact_candidates",
    "horner",
    "polyval",
    "real_roots",
    "segment_index",
    "unit_roots",
]

FloatArray = NDArray[np.float64]

#: Relative size below which a leading polynomial coefficient is treated as zero when its
#: roots are sought (a few machine epsilons: dropping it moves the polynomial by less than
#: that fraction of its largest coefficient on the segment).
_NEGLIGIBLE = 64.0 * float(np.finfo(float).eps)


def derivatives_of(coefficients: FloatArray, count: int) -> list[FloatArray]:
    """Coefficients of the position polynomial and its first ``count`` time derivatives.

    Args:
        coefficients: Shape (K, d + 1, n), ascending powers of the local time.
        count: Number of derivatives.

    Returns:
        ``count + 1`` arrays, the r-th of shape (K, max(d + 1 - r, 1), n).
    """
    result = [np.asarray(coefficients, dtype=float)]
    for _ in range(count):
        last = result[-1]
        if last.shape[1] == 1:
            result.append(np.zeros_like(last))
        else:
            powers = np.arange(1, last.shape[1], dtype=float)[None, :, None]
            result.append(last[:, 1:, :] * powers)
    return result


def segment_index(knots: FloatArray, times: FloatArray) -> NDArray[np.intp]:
    """Segment index of each time (right-continuous, the last segment at the end time)."""
    index = np.searchsorted(knots, times, side="right") - 1
    return np.clip(index, 0, len(knots) - 2)


def evaluate_piecewise(
    coefficients: FloatArray, knots: FloatArray, times: FloatArray
) -> FloatArray:
    """Piecewise polynomial values at the given times, shape (m, n)."""
    segment = segment_index(knots, times)
    tau = (times - knots[segment])[:, None]
    rows = coefficients[segment]
    result = rows[:, -1, :].copy()
    for i in range(rows.shape[1] - 2, -1, -1):
        result = result * tau + rows[:, i, :]
    return result


def polyval(coefficients: FloatArray, tau: FloatArray) -> FloatArray:
    """One polynomial (ascending coefficients) at local times ``tau``."""
    result = np.full(np.shape(tau), coefficients[-1], dtype=float)
    for c in coefficients[-2::-1]:
        result = result * tau + c
    return result


def critical_points(coefficients: FloatArray, length: float) -> FloatArray:
    """Local times in [0, length] where a polynomial may take its extremes.

    The two ends and the (nearly) real roots of its derivative; extra candidates only cost an
    evaluation, so nearly real roots (double roots come out slightly complex) are kept.
    """
    candidates = [np.array([0.0, length])]
    if coefficients.size > 1:
        slope = coefficients[1:] * np.arange(1, coefficients.size)
        candidates.append(real_roots(slope, length))
    return np.concatenate(candidates)


def real_roots(coefficients: FloatArray, length: float) -> FloatArray:
    """Nearly real roots of a polynomial (ascending coefficients) within [0, length]."""
    if not np.any(coefficients):
        return np.empty(0)
    roots = np.roots(coefficients[::-1])
    near = roots[np.abs(roots.imag) <= 1e-6 * (length + np.abs(roots.real))].real
    return np.clip(near[(near > -1e-9 * length) & (near < length * (1 + 1e-9))], 0.0, length)


def horner(coefficients: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Value and derivative of each row's polynomial at its points, by Horner's scheme.

    Args:
        coefficients: Ascending powers, one polynomial per row, shape (R, d + 1).
        u: Points, shape (R, c).

    Returns:
        (value, derivative), each shape (R, c).
    """
    value = np.zeros_like(u)
    derivative = np.zeros_like(u)
    for i in range(coefficients.shape[1] - 1, -1, -1):
        derivative = derivative * u + value
        value = value * u + coefficients[:, i : i + 1]
    return value, derivative


def unit_roots(slope: FloatArray) -> FloatArray:
    """Real parts of the roots of many polynomials, clipped onto [0, 1].

    Each row holds ascending coefficients; leading coefficients below ``_NEGLIGIBLE`` times
    the row's largest are dropped, and the rows of each remaining degree share one batched
    eigenvalue call on their companion matrices. The real part of a complex root is kept
    too (clipped, it is still a point of the segment, so it can only add a candidate), and
    each root is improved by one Newton step, kept as a further candidate.

    Args:
        slope: Coefficients, shape (N, m + 1).

    Returns:
        Candidate points, shape (N, 2 m); 0 where a row has fewer roots.
    """
    rows, width = slope.shape
    found = np.zeros((rows, 2 * (width - 1)))
    size = np.abs(slope)
    significant = size > _NEGLIGIBLE * size.max(axis=1, keepdims=True)
    degree = np.where(
        significant.any(axis=1), width - 1 - np.argmax(significant[:, ::-1], axis=1), 0
    )
    for m in range(1, width):
        which = np.flatnonzero(degree == m)
        if which.size == 0:
            continue
        c = slope[which, : m + 1]
        companion = np.zeros((which.size, m, m))
        companion[:, np.arange(1, m), np.arange(m - 1)] = 1.0
        companion[:, :, -1] = -c[:, :m] / c[:, m : m + 1]
        u = np.clip(np.linalg.eigvals(companion).real, 0.0, 1.0)  # (N_m, m)
        value, derivative = horner(c, u)
        # A near-zero derivative overflows the Newton step: the clip below keeps the root
        # in the segment, and the unpolished root u is a candidate too.
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = np.where(derivative != 0.0, value / derivative, 0.0)
        polished = np.clip(np.nan_to_num(u - step, nan=0.0), 0.0, 1.0)
        found[which, :m] = u
        found[which, width - 1 : width - 1 + m] = polished
    return found


#: A convex score of a joint quantity: values (any shape) and the joint of each (broadcast
#: with them) in, scores out; larger is worse.
Score = Callable[[FloatArray, NDArray[np.intp]], FloatArray]


@functools.cache
def bernstein(degree: int) -> FloatArray:
    """Matrix from power to Bernstein coefficients on [0, 1], shape (degree + 1, degree + 1).

    ``b_k = sum_{i <= k} C(k, i) / C(degree, i) a_i``; a polynomial on [0, 1] lies between
    its smallest and largest Bernstein coefficient (Farouki & Rajan, "On the numerical
    condition of polynomials in Bernstein form", CAGD 4(3), 1987).
    """
    matrix = np.zeros((degree + 1, degree + 1))
    for k in range(degree + 1):
        for i in range(k + 1):
            matrix[i, k] = math.comb(k, i) / math.comb(degree, i)
    return matrix


@dataclass(frozen=True)
class Candidates:
    """Instants where a joint quantity may take its worst value, flat over segments and joints.

    Attributes:
        time: The instants [s] (a segment's end is its breakpoint exactly), shape (M,).
        value: The quantity there [unit], shape (M,).
        slope: Its time derivative there [unit/s], shape (M,).
        joint: The joint of each, shape (M,).
    """

    time: FloatArray
    value: FloatArray
    slope: FloatArray
    joint: NDArray[np.intp]


def exact_candidates(
    knots: FloatArray, coefficients: FloatArray, score: Score, fails: float
) -> Candidates:
    """Candidates that hold the exact worst score of one joint quantity, on every segment.

    Every segment's two ends are candidates. A segment's interior can only matter when its
    Bernstein enclosure (a rigorous bound of the polynomial on the segment) scores above the
    best end or above ``fails`` (where a value starts to fail); for those (segment, joint)
    pairs the real roots of the derivative are added (:func:`unit_roots`). So the largest
    score over the candidates is the exact largest over the whole trajectory, whatever the
    sampling rate, and no value that fails is left out; vectorised over segments and joints.

    Args:
        knots: Breakpoints [s], shape (K + 1,).
        coefficients: The quantity's piecewise polynomial (one entry of
            :func:`derivatives_of`), shape (K, d + 1, n).
        score: Convex score per joint (larger is worse), so its largest value over an
            interval of values is at one of the interval's ends.
        fails: The score above which a value may fail.
    """
    _, width, n = coefficients.shape
    h = np.diff(knots)
    scaled = coefficients * (h[:, None] ** np.arange(width, dtype=float))[:, :, None]
    powers = np.arange(width, dtype=float)[None, :, None]
    joints = np.arange(n)
    value = np.stack([scaled[:, 0, :], scaled.sum(axis=1)], axis=1)  # (K, 2, n): u = 0, 1
    if width == 1:
        slope = np.zeros_like(value)
    else:
        slope = np.stack([scaled[:, 1, :], (scaled * powers).sum(axis=1)], axis=1)
        slope /= h[:, None, None]
    time = np.broadcast_to(np.stack([knots[:-1], knots[1:]], axis=1)[:, :, None], value.shape)
    found = [
        (time.ravel(), value.ravel(), slope.ravel(), np.broadcast_to(joints, value.shape).ravel())
    ]
    if width > 2:
        best = float(np.max(score(value, joints)))
        threshold = min(best, fails)
        enclosure = np.einsum("kin,ij->kjn", scaled, bernstein(width - 1))
        bound = np.maximum(
            score(enclosure.min(axis=1), joints), score(enclosure.max(axis=1), joints)
        )
        k, j = np.nonzero(bound >= threshold - round_off(threshold))
        if k.size:
            rows = scaled[k, :, j]  # (R, width)
            derivative = rows[:, 1:] * np.arange(1, width, dtype=float)
            u = unit_roots(derivative)  # (R, c)
            inner_value, inner_slope = horner(rows, u)
            length = h[k][:, None]
            found.append(
                (
                    (knots[k][:, None] + u * length).ravel(),
                    inner_value.ravel(),
                    (inner_slope / length).ravel(),
                    np.broadcast_to(j[:, None], u.shape).ravel(),
                )
            )
    times, values, slopes, which = (np.concatenate(parts) for parts in zip(*found, strict=True))
    return Candidates(times, values, slopes, which)
