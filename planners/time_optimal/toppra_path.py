r"""Geometric joint paths for TOPPRA: piecewise polynomials in the path parameter s.

:class:`GeometricPath` is the path :class:`~planners.time_optimal.toppra_planner.Toppra`
retimes: a not-a-knot cubic spline through waypoints (:meth:`GeometricPath.spline`, s =
cumulative chord length), a shape-preserving PCHIP cubic through them
(:meth:`GeometricPath.pchip`, used where the spline would leave the joint limits), the
straight joint-space line (:meth:`GeometricPath.line`) or a trajectory's positions over its
own time (:meth:`GeometricPath.from_trajectory`, s = its time). The functions here evaluate
and differentiate such piecewise polynomials
(:func:`~planners.time_optimal.toppra_path_checks.waypoint_path` chooses the spline or the
PCHIP cubic for waypoints). :attr:`GeometricPath.native` is the same path as a toppra path
object (:class:`~planners.time_optimal.toppra_classes.PolynomialPath`); :func:`toppra_classes`
imports the module of such toppra-derived classes on first use.

Example::

    path = GeometricPath.spline(waypoints)   # waypoints: shape (k, n)
    first, second = path.derivatives          # coefficients of q'(s) and q''(s)
    path.native(path.knots, 1)                # q'(s) at the knots, shape (k, n)
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import cached_property
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.planners.trajectory import Trajectory

__all__ = [
    "GeometricPath",
    "curvature_jumps",
    "derivative",
    "polyval_grid",
    "polyval_local",
    "segment_of",
    "toppra_classes",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class GeometricPath:
    r"""A geometric joint path, piecewise polynomial in the path parameter s.

    .. math:: q_j(s) = \sum_{i=0}^{d} c_{k,i,j}\,(s - s_k)^i, \qquad s_k \le s < s_{k+1}

    Attributes:
        knots: Segment boundaries [path units], shape (m + 1,), increasing.
        coefficients: Local polynomial coefficients, shape (m, d + 1, n), ascending powers
            [rad/(path unit)^i or m/(path unit)^i].
        kind: How the path was made, e.g. ``"cubic spline (not-a-knot)"``.
        unit: The path unit, ``"rad"`` (joint-space chord length) or ``"s"`` (a trajectory's
            time).
    """

    knots: FloatArray
    coefficients: FloatArray
    kind: str
    unit: str

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.coefficients.shape[2])

    @cached_property
    def derivatives(self) -> tuple[FloatArray, FloatArray]:
        """Coefficients of q'(s) and q''(s), shapes (m, d, n) and (m, d - 1, n)."""
        first = derivative(self.coefficients)
        return first, derivative(first)

    @cached_property
    def native(self) -> Any:
        """The path as a toppra ``AbstractGeometricPath`` (imports toppra on first use)."""
        return toppra_classes().PolynomialPath(self)

    @cached_property
    def rest_points(self) -> FloatArray:
        """Inner knots where the path stops dead: q' and q'' vanish on both sides.

        A trajectory used as a path does this where it comes to rest with zero acceleration
        (a rest-to-rest quintic) or dwells (a segment at rest between two such knots).
        There every constraint vanishes, so toppra, which checks them only at gridpoints,
        would let the path velocity leap up at the knot and break the limits just before
        it; the path velocity is held at (nearly) 0 there instead, as at a path's ends.
        """
        coeffs = self.coefficients
        if coeffs.shape[0] < 2 or self.unit != "s":  # chord-length paths never stop
            return np.empty(0)
        lengths = np.diff(self.knots)[:-1]
        span = self.knots[-1] - self.knots[0]
        speed = self.length / span  # typical |q'| [rad / path unit]
        still = np.ones(lengths.size, dtype=bool)
        for order, scale in ((0, speed), (1, speed / span)):
            rows = self.derivatives[order]
            left = np.abs(polyval_local(rows[:-1], lengths))
            right = np.abs(rows[1:, 0, :])
            still &= np.max(np.maximum(left, right), axis=1) <= 1e-9 * scale
        return self.knots[1:-1][still]

    @cached_property
    def length(self) -> float:
        """Sum of the segments' joint-space chords [rad or m] (a length estimate)."""
        ends = polyval_local(self.coefficients, np.diff(self.knots))
        return float(np.sum(np.linalg.norm(ends - self.coefficients[:, 0, :], axis=1)))

    def stretched(self, factor: float) -> GeometricPath:
        """The same path in the parameter ``factor * s`` (knots times factor, > 0)."""
        powers = np.arange(self.coefficients.shape[1], dtype=float)
        coefficients = self.coefficients * (factor**-powers)[None, :, None]
        return GeometricPath(self.knots * factor, coefficients, self.kind, self.unit)

    @classmethod
    def spline(cls, waypoints: FloatArray) -> GeometricPath:
        """The not-a-knot cubic spline through waypoints, s = cumulative chord length.

        The same spline as ``toppra.SplineInterpolator`` (scipy's ``CubicSpline``, its
        default not-a-knot ends): a line through two waypoints, a parabola through three,
        else C2 cubics whose third derivative is continuous at the second and the
        second-to-last waypoints. Solved here for the second derivatives M at the
        waypoints (one small dense system for all joints).

        Args:
            waypoints: Configurations [rad or m], shape (k, n), k >= 2, consecutive ones
                distinct.
        """
        s = _chord_lengths(waypoints)
        h = np.diff(s)
        delta = np.diff(waypoints, axis=0) / h[:, None]
        k = s.size
        moments: NDArray[np.floating[Any]]
        if k == 2:
            moments = np.zeros_like(waypoints)
        elif k == 3:
            moments = np.broadcast_to(2.0 * (delta[1] - delta[0]) / (h[0] + h[1]), waypoints.shape)
        else:
            system = np.zeros((k, k))
            rhs = np.zeros_like(waypoints)
            inner = np.arange(1, k - 1)
            system[inner, inner - 1] = h[:-1]
            system[inner, inner] = 2.0 * (h[:-1] + h[1:])
            system[inner, inner + 1] = h[1:]
            rhs[1:-1] = 6.0 * (delta[1:] - delta[:-1])
            # not-a-knot: the third derivative is continuous at s_1 and at s_(k-2)
            system[0, :3] = [h[1], -(h[0] + h[1]), h[0]]
            system[-1, -3:] = [h[-1], -(h[-2] + h[-1]), h[-2]]
            moments = np.linalg.solve(system, rhs)
        m0, m1 = moments[:-1], moments[1:]
        hh = h[:, None]
        coeffs = np.stack(
            [waypoints[:-1], delta - hh * (2.0 * m0 + m1) / 6.0, 0.5 * m0, (m1 - m0) / (6.0 * hh)],
            axis=1,
        )
        return cls(s, coeffs, "cubic spline (not-a-knot)", "rad")

    @classmethod
    def pchip(cls, waypoints: FloatArray) -> GeometricPath:
        """A shape-preserving (PCHIP) cubic through waypoints, s = cumulative chord length.

        Only C1, but on each segment every joint stays between its two waypoint values
        (Fritsch-Carlson slopes: zero at a joint's local extrema, weighted harmonic means
        elsewhere, limited one-sided slopes at the ends), so the path never leaves a box
        that holds the waypoints.

        Args:
            waypoints: Configurations [rad or m], shape (k, n), k >= 2, consecutive ones
                distinct.
        """
        s = _chord_lengths(waypoints)
        h = np.diff(s)[:, None]
        delta = np.diff(waypoints, axis=0) / h
        slope = np.zeros_like(waypoints)
        if len(s) == 2:
            slope[:] = delta[0]
        else:
            w1 = 2.0 * h[1:] + h[:-1]
            w2 = h[1:] + 2.0 * h[:-1]
            same = delta[:-1] * delta[1:] > 0.0
            # A slope near zero makes its term overflow to inf and the mean tend to 0, its
            # limit (this weighted harmonic mean is at most 3 times its smaller slope).
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                mean = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
            slope[1:-1] = np.where(same, mean, 0.0)
            slope[0] = _pchip_end(h[0], h[1], delta[0], delta[1])
            slope[-1] = _pchip_end(h[-1], h[-2], delta[-1], delta[-2])
        d0, d1 = slope[:-1], slope[1:]
        coeffs = np.stack(
            [waypoints[:-1], d0, (3.0 * delta - 2.0 * d0 - d1) / h, (d0 + d1 - 2.0 * delta) / h**2],
            axis=1,
        )
        return cls(s, coeffs, "pchip cubic", "rad")

    @classmethod
    def line(cls, q_start: FloatArray, q_goal: FloatArray) -> GeometricPath:
        """The straight joint-space line, s = distance travelled [rad or m]."""
        delta = q_goal - q_start
        length = float(np.linalg.norm(delta))
        coeffs = np.stack([q_start, delta / length])[None]
        return cls(np.array([0.0, length]), coeffs, "straight line", "rad")

    @classmethod
    def from_trajectory(cls, trajectory: Trajectory) -> GeometricPath:
        """A trajectory's positions over its own time as a path (s = its time [s])."""
        coeffs = np.asarray(trajectory.coefficients, dtype=float)
        if coeffs.shape[1] == 1:  # constant pieces: give them a (zero) slope term
            coeffs = np.concatenate([coeffs, np.zeros_like(coeffs)], axis=1)
        planner = trajectory.metadata.get("planner")
        made = "" if planner is None else f" from {planner!r}"
        kind = f"trajectory{made} (degree {coeffs.shape[1] - 1})"
        return cls(np.asarray(trajectory.breakpoints, dtype=float), coeffs, kind, "s")


def _chord_lengths(waypoints: FloatArray) -> FloatArray:
    """Cumulative joint-space chord length at each waypoint [rad or m], shape (k,)."""
    steps = np.sqrt(np.sum(np.diff(waypoints, axis=0) ** 2, axis=1))
    return np.concatenate([[0.0], np.cumsum(steps)])


def _pchip_end(h0: FloatArray, h1: FloatArray, d0: FloatArray, d1: FloatArray) -> FloatArray:
    """End slope of a PCHIP: one-sided three-point estimate, limited to keep the shape."""
    slope = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
    slope = np.where(np.sign(slope) != np.sign(d0), 0.0, slope)
    limit = (np.sign(d0) != np.sign(d1)) & (np.abs(slope) > 3.0 * np.abs(d0))
    return np.where(limit, 3.0 * d0, slope)


def polyval_local(coefficients: FloatArray, tau: FloatArray) -> FloatArray:
    """Each segment's polynomial at its own local coordinate, shape (m, n) for tau (m,)."""
    result = coefficients[:, -1, :].copy()
    for i in range(coefficients.shape[1] - 2, -1, -1):
        result = result * tau[:, None] + coefficients[:, i, :]
    return result


def segment_of(knots: FloatArray, s: FloatArray) -> NDArray[np.intp]:
    """Segment of each path position (a position on a knot: the segment that starts there)."""
    return np.clip(np.searchsorted(knots, s, side="right") - 1, 0, knots.size - 2)


def polyval_grid(rows: FloatArray, sigma: FloatArray) -> FloatArray:
    """Polynomials ``rows`` (shape (N, d + 1, n)) at local coordinates ``sigma`` (N, P).

    Returns:
        Values, shape (N, P, n).
    """
    x = sigma[:, :, None]
    result = np.broadcast_to(rows[:, None, -1, :], (*sigma.shape, rows.shape[2]))
    for i in range(rows.shape[1] - 2, -1, -1):
        result = result * x + rows[:, None, i, :]
    return np.asarray(result)


def derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients of the derivative, one degree lower (at least degree 0)."""
    if coefficients.shape[1] == 1:
        return np.zeros_like(coefficients)
    powers = np.arange(1, coefficients.shape[1], dtype=float)[None, :, None]
    return coefficients[:, 1:, :] * powers


def curvature_jumps(
    knots: FloatArray, coefficients: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Inner knots where a path's second derivative jumps, with the path's state there.

    Returns:
        (s, q, q', left q''): the knots, shape (k,), and the position, first derivative and
        second derivative of the segment that ends there, each shape (k, n).
    """
    n = coefficients.shape[2]
    if coefficients.shape[0] < 2 or coefficients.shape[1] < 3:
        empty = np.empty((0, n))
        return np.empty(0), empty, empty, empty
    first = derivative(coefficients)
    second = derivative(first)
    left = polyval_local(second[:-1], np.diff(knots)[:-1])
    right = second[1:, 0, :]
    scale = np.max(np.abs(right)) + np.max(np.abs(left)) + 1e-300
    at = np.flatnonzero(np.max(np.abs(left - right), axis=1) > 1e-9 * scale)
    return knots[at + 1], coefficients[at + 1, 0, :], first[at + 1, 0, :], left[at]


def toppra_classes() -> ModuleType:
    """The module :mod:`planners.time_optimal.toppra_classes`, imported on first use.

    It imports toppra (and with it matplotlib and scipy), which ``import optraj.planners``
    must not, and it imports this module: so the modules that build toppra objects reach
    its classes through this function, at call time, never by a module-level import.
    """
    return importlib.import_module("optraj.planners.time_optimal.toppra_classes")
