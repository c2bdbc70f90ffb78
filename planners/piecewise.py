r"""Piecewise polynomials as arrays: checked, differentiated, interpolated, joined.

The arrays are those of :class:`~optraj.planners.trajectory.Trajectory`: breakpoints of shape
(K + 1,) and coefficients of shape (K, d + 1, n), ``coefficients[k, i, j]`` multiplying
``(t - t_k)^i`` for joint j on segment k. :func:`hermite_pieces` interpolates joint states
(behind :meth:`Trajectory.from_hermite <optraj.planners.trajectory.Trajectory.from_hermite>`),
:func:`joined` plays trajectories one after another (behind ``then`` and ``sequence``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.phase import Phase, shifted
from optraj.validation import MAX_DURATION, as_array, as_number, as_vector

if TYPE_CHECKING:
    from optraj.planners.trajectory import Trajectory

__all__ = [
    "built_pieces",
    "hermite_pieces",
    "joined",
    "validated_pieces",
    "with_derivatives",
]

FloatArray = NDArray[np.float64]


def validated_pieces(
    breakpoints: ArrayLike, coefficients: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Breakpoints and coefficients checked against each other, as read-only arrays.

    Float arrays that pass every check take a shorter path (:func:`_checked_arrays`); anything
    else, and anything that fails, goes through the checks below, which name the fault.

    Raises:
        InvalidInputError: Not one coefficient row per segment, no term or no joint,
            breakpoints that do not strictly increase from 0 or end beyond MAX_DURATION,
            or non-finite values.
    """
    checked = _checked_arrays(breakpoints, coefficients)
    if checked is not None:
        return checked
    knots = as_vector(breakpoints, "breakpoints")
    coeffs = as_array(coefficients, "coefficients", (None, None, None))
    if knots.size < 2 or coeffs.shape[0] != knots.size - 1:
        raise InvalidInputError(
            f"coefficients must have one row per segment: {knots.size} breakpoints need "
            f"shape ({knots.size - 1}, degree + 1, n), got {coeffs.shape}",
            name="coefficients",
        )
    if coeffs.shape[1] < 1 or coeffs.shape[2] < 1:
        raise InvalidInputError(
            f"coefficients must have at least one term and one joint, got {coeffs.shape}",
            name="coefficients",
        )
    if knots[0] != 0.0 or np.any(np.diff(knots) <= 0.0):
        raise InvalidInputError(
            "breakpoints must start at 0 s and strictly increase, got "
            f"{np.array2string(knots, precision=6, threshold=8)}",
            name="breakpoints",
        )
    as_number(knots[-1], "duration (last breakpoint)", "s", maximum=MAX_DURATION)
    for array in (knots, coeffs):
        array.setflags(write=False)
    return knots, coeffs


#: Native float64, the one element type :func:`_checked_arrays` takes.
_FLOAT = np.dtype(np.float64)


def _checked_arrays(
    breakpoints: ArrayLike, coefficients: ArrayLike
) -> tuple[FloatArray, FloatArray] | None:
    """Read-only copies of float64 arrays that pass every check of :func:`validated_pieces`.

    None for anything else (other types, or a failed check): the full checks then run and
    raise.
    """
    if not (
        type(breakpoints) is np.ndarray
        and type(coefficients) is np.ndarray
        and breakpoints.dtype is _FLOAT
        and coefficients.dtype is _FLOAT
        and breakpoints.ndim == 1
        and coefficients.ndim == 3
    ):
        return None
    size = breakpoints.shape[0]
    shape = coefficients.shape
    if size < 2 or shape[0] != size - 1 or shape[1] < 1 or shape[2] < 1:
        return None
    last = float(breakpoints[-1])
    if breakpoints[0] != 0.0 or not 0.0 < last <= MAX_DURATION:
        return None
    if size > 2 and not (breakpoints[1:] > breakpoints[:-1]).all():
        return None
    if not np.isfinite(coefficients).all():
        return None
    knots, coeffs = breakpoints.copy(), coefficients.copy()
    knots.flags.writeable = False
    coeffs.flags.writeable = False
    return knots, coeffs


def built_pieces(
    build: Callable[[], tuple[ArrayLike, ArrayLike]], duration: float, dof: int
) -> tuple[FloatArray, FloatArray]:
    """The pieces a deferred trajectory's ``build`` returns, checked as :func:`validated_pieces`.

    Raises:
        InvalidInputError: Pieces that do not end at ``duration`` [s] or are not of ``dof``
            joints (and any error of :func:`validated_pieces`).
    """
    knots, coeffs = validated_pieces(*build())
    if knots[-1] != duration or coeffs.shape[2] != dof:
        raise InvalidInputError(
            f"a deferred trajectory of {duration!r} s and {dof} joints was "
            f"built with {knots[-1]!r} s and {coeffs.shape[2]} joints",
            name="build",
        )
    return knots, coeffs


#: The powers 1 .. d that differentiate a polynomial of degree d, for the common degrees.
_POWERS = {degree: np.arange(1.0, degree + 1.0)[None, :, None] for degree in range(1, 8)}


def _derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients of the time derivative, one degree lower (at least degree 0)."""
    degree = coefficients.shape[1] - 1
    if degree == 0:
        return np.zeros_like(coefficients)
    powers = _POWERS.get(degree)
    if powers is None:
        powers = np.arange(1, degree + 1, dtype=float)[None, :, None]
    return coefficients[:, 1:, :] * powers


def with_derivatives(coefficients: FloatArray) -> list[FloatArray]:
    """Coefficients of a polynomial and of its first three time derivatives."""
    result = [coefficients]
    for _ in range(3):
        result.append(_derivative(result[-1]))
    return result


def _cubic_hermite(
    p0: FloatArray, p1: FloatArray, v0: FloatArray, v1: FloatArray, h: FloatArray | float
) -> list[FloatArray]:
    """Coefficients ``[c0, c1, c2, c3]`` of the cubic from (p0, v0) to (p1, v1) in time h [s].

    Every argument broadcasts with the others (one segment or many, one joint or many).
    """
    c2 = (3 * (p1 - p0) - (2 * v0 + v1) * h) / h**2
    c3 = (2 * (p0 - p1) + (v0 + v1) * h) / h**3
    return [p0, v0, c2, c3]


def _quintic_hermite(
    p0: FloatArray,
    p1: FloatArray,
    v0: FloatArray,
    v1: FloatArray,
    a0: FloatArray,
    a1: FloatArray,
    h: FloatArray | float,
) -> list[FloatArray]:
    """Coefficients ``[c0, ..., c5]`` of the quintic from (p0, v0, a0) to (p1, v1, a1) in h [s].

    The end conditions on c3, c4, c5 form a 3x3 linear system, solved here in closed form
    (the start gives c0 = p0, c1 = v0, c2 = a0 / 2). Arguments broadcast as for
    :func:`_cubic_hermite`.
    """
    dp = p1 - p0 - v0 * h - 0.5 * a0 * h**2
    dv = v1 - v0 - a0 * h
    da = a1 - a0
    c3 = (20 * dp - 8 * dv * h + da * h**2) / (2 * h**3)
    c4 = (-30 * dp + 14 * dv * h - 2 * da * h**2) / (2 * h**4)
    c5 = (12 * dp - 6 * dv * h + da * h**2) / (2 * h**5)
    return [p0, v0, 0.5 * a0, c3, c4, c5]


def hermite_pieces(
    times: ArrayLike, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike | None = None
) -> tuple[FloatArray, FloatArray]:
    """Breakpoints and coefficients through sampled states, as for ``Trajectory.from_hermite``.

    Cubic segments from (q, qd), quintic ones when qdd is given too; the breakpoints are the
    times moved to start at 0.

    Raises:
        InvalidInputError: Arrays of the wrong shapes or times that do not strictly increase.
    """
    t = as_vector(times, "times")
    m = t.size
    pos = as_array(q, "q", (m, None))
    vel = as_array(qd, "qd", pos.shape)
    h = np.diff(t)[:, None]
    if np.any(h <= 0.0):
        raise InvalidInputError("times must strictly increase", name="times")
    p0, p1, v0, v1 = pos[:-1], pos[1:], vel[:-1], vel[1:]
    if qdd is None:
        coeffs = np.stack(_cubic_hermite(p0, p1, v0, v1, h), axis=1)
    else:
        acc = as_array(qdd, "qdd", pos.shape)
        coeffs = np.stack(_quintic_hermite(p0, p1, v0, v1, acc[:-1], acc[1:], h), axis=1)
    return t - t[0], coeffs


def joined(pieces: Sequence[Trajectory]) -> tuple[FloatArray, FloatArray, list[Phase]]:
    """Breakpoints, coefficients and phases of trajectories played one after another.

    Each piece is shifted to start where the previous one ends, its degree raised to the
    highest one (zero coefficients), its phases shifted along. The pieces must have the same
    number of joints; continuity between them is not enforced.
    """
    degree = max(piece.degree for piece in pieces)
    knots: list[FloatArray] = []
    rows: list[FloatArray] = []
    phases: list[Phase] = []
    offset = 0.0
    for piece in pieces:
        knots.append(piece.breakpoints[:-1] + offset)
        coeffs = piece.coefficients
        pad = np.zeros((coeffs.shape[0], degree + 1, coeffs.shape[2]))
        pad[:, : coeffs.shape[1], :] = coeffs
        rows.append(pad)
        phases.extend(shifted(piece.phases, offset))
        offset += piece.duration
    knots.append(np.array([offset]))
    return np.concatenate(knots), np.concatenate(rows), phases
