r"""Time-optimal retiming of a geometric joint path with TOPPRA, as exact optraj trajectories.

TOPPRA (``pip install toppra``; Pham & Pham, "A new approach to time-optimal path
parameterization based on reachability analysis", IEEE T-RO 2018) takes a path
:math:`q(s)`, :math:`s \in [s_0, s_N]`, and constraints that are linear in the path
acceleration :math:`u = \ddot s` and the squared path velocity :math:`x = \dot s^2`,

.. math:: \dot q = q'(s)\,\dot s, \qquad \ddot q = q'(s)\,u + q''(s)\,x,

and finds the fastest :math:`\dot s` on a grid :math:`s_0 < s_1 < \dots < s_N` with small
linear programs, backwards (controllable sets) then forwards (greedy). This module wraps it.

Paths
    :meth:`Toppra.plan` takes a :class:`problems.Waypoints` (a not-a-knot cubic spline through
    the waypoints, :math:`s` = cumulative chord length; a shape-preserving PCHIP cubic instead
    when the spline would leave the joint limits) or a :class:`problems.PointToPoint` (the
    straight joint-space line). :meth:`Toppra.time_parametrize` retimes an array of waypoints
    the same way, or any :class:`~planners.trajectory.Trajectory` used as a geometric path:
    its positions over its own time are the path (:math:`s` = its time) and its phases are
    carried over to the new times.

Constraints
    Joint velocity and acceleration limits; optionally joint torques (toppra's
    ``JointTorqueConstraint`` fed by the robot's RNEA, no friction) and a cap on the tool
    frame origin's speed, :math:`\lVert J_v(q)\,q'(s)\rVert\,\dot s \le v_{max}`. All are
    toppra canonical linear constraints. Speed caps (joint velocities, tool speed) are upper
    bounds on :math:`x` at each gridpoint, so they only fill the ``xbound`` column, as
    toppra's ``JointVelocityConstraint`` does, and cost the stage-wise programs nothing;
    unlike it, the bounds are chosen to hold between gridpoints too (at 100 gridpoints,
    toppra's own lets joint speeds overshoot by a few percent, up to 17 % in random tests).
    Accelerations and torques are discretised like toppra's "interpolation" scheme (both
    ends of each grid interval), with two fixes: at a knot where the path's curvature jumps
    the interval ending there uses the curvature before the knot, and every row is
    normalised, because toppra's Seidel solver uses absolute tolerances and otherwise
    reports an empty controllable set on feasible paths where a joint barely moves.

Output
    With toppra's ``ParametrizeConstAccel`` the path acceleration is constant on each grid
    interval, so :math:`s(t)` is quadratic there; the path is a piecewise cubic (or any
    piecewise polynomial) in :math:`s`, and every knot is a gridpoint, so on each grid
    interval :math:`q(t)` is one polynomial of twice the path's degree (6 for a cubic).
    :func:`compose` builds these exactly: the trajectory *is* toppra's answer, sampled
    nowhere. toppra's own output object is kept in ``metadata["native"]``.

Between gridpoints
    toppra imposes its constraints only at the gridpoints (here at both ends of each grid
    interval, toppra's "interpolation" discretisation), so in between a limit can be
    exceeded slightly. Three measures keep the result within the limits:

    * speed caps use bounds that also hold between gridpoints (:func:`chord_safe_bound`);
    * every rate limit is shrunk by :data:`MARGIN` before solving;
    * the result is verified: on each grid interval joint velocity and acceleration are
      polynomials in time, bounded exactly (from above) by their Bernstein coefficients,
      computed from as many samples as their degree needs (6 for a cubic path; torques and
      the tool speed are bounded the same way, as estimates). Where a bound still exceeds
      ``1 - MARGIN / 2`` of its limit, a rest-to-rest motion is slowed down uniformly in
      time just enough (speeds scale by c, accelerations by c^2), and a motion with a
      moving start or end is solved again with that limit shrunk further (it cannot be
      slowed without changing its boundary velocities). ``metadata["limit_ratio"]`` holds
      the bounds, ``metadata["slowdown"]`` the factor on the duration.

Failures
    Typed errors, never ``None``: a path through a joint limit (:class:`JointLimitError`
    naming the joint and the path position), a torque limit that gravity alone breaks on the
    path, a start or end path velocity beyond what the limits allow (the requested and the
    largest feasible value), an empty controllable set (its grid index and path position)
    are :class:`InfeasibleError`; a failed forward pass is a :class:`SolverError`.

Example::

    robot = robots.load("sawyer")
    problem = problems.Waypoints(robot, robot.random_configurations(4, rng))
    traj = Toppra().plan(problem)
    traj.metadata["native"]  # toppra's ParametrizeConstAccel output
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache, cached_property
from types import ModuleType
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, JointLimitError, SolverError
from optraj.planners.base import stamp
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PointToPoint, Waypoints
from optraj.problems.common import MAX_TOOL_SPEED
from optraj.problems.point_to_point import STILL_TOLERANCE, still_error
from optraj.robots import JointLimits, Robot
from optraj.validation import (
    MIN_DURATION,
    as_array,
    as_count,
    as_flag,
    as_number,
    as_positive,
)

__all__ = [
    "MARGIN",
    "MAX_GRIDPOINTS",
    "RETRIES",
    "GeometricPath",
    "Toppra",
    "ToppraProblem",
    "compose",
]

FloatArray = NDArray[np.float64]

#: Fraction by which every rate limit (velocity, acceleration, torque, tool speed) is shrunk
#: before solving, to absorb toppra's small excess between gridpoints [-].
MARGIN = 1e-3
#: Re-solves after the verification: with a finer grid where the limits are exceeded by
#: more than a small slow-down fixes, or (a motion with a moving start or end, which
#: cannot be slowed down) with the exceeded limits shrunk further.
RETRIES = 2
#: Most grid intervals a planner may ask for: a straight Sawyer move on 20,000 intervals
#: solved in 0.6 s here, so this many take seconds, and far fewer (the default is at most
#: 400) already resolve a path; a count of 10**7 would exhaust the memory first.
MAX_GRIDPOINTS = 100_000
#: Default grid: one interval per this much joint-space path length [rad or m] ...
_GRID_STEP = 0.02
#: ... but no fewer and no more intervals than these.
_MIN_GRID = 100
_MAX_GRID = 400
#: Paths shorter than this many path units are solved in a stretched parameter (see
#: :func:`_stretch`).
_STRETCH_BELOW = 1.0
#: Verified ratios up to this pass; above it a motion is slowed down or solved again.
_TARGET = 1.0 - 0.5 * MARGIN
#: Largest squared path velocity offered to toppra where nothing bounds it.
_X_CAP = 1e16
#: Fractions of each grid interval at which speed caps are also evaluated.
_INTERIOR = np.array([0.25, 0.5, 0.75])
#: Parts into which a grid interval whose bound exceeds the target is split and bounded again.
_SUBDIVIDE = 8
#: A slow-down by more than this fraction of the duration is avoided by refining the grid
#: where the limits are exceeded and solving again (at most :data:`RETRIES` times).
_REFINE_ABOVE = 0.005


# ------------------------------------------------------------------------------ toppra


@cache
def _lib() -> ModuleType:
    """:mod:`optraj.planners.time_optimal.toppra_classes`, imported on the first plan.

    It holds toppra's return code and discretisation and our classes derived from toppra's.
    Importing toppra imports matplotlib.pyplot and scipy.interpolate (about 0.7 s), so it is
    imported on the first plan and ``from optraj import planners`` stays fast.
    """
    from optraj.planners.time_optimal import toppra_classes

    return toppra_classes


def chord_safe_bound(
    rates: Callable[[Any, FloatArray], FloatArray], path: Any, grid: FloatArray
) -> FloatArray:
    r"""Upper bounds on :math:`x = \dot s^2` at the gridpoints that also hold in between.

    Let :math:`B(s) = 1 / \max_k r_k(s)^2` be the largest allowed :math:`x`. toppra keeps
    :math:`x_i \le B(s_i)`, but the output's :math:`x(s)` is linear on each grid interval and
    can rise above :math:`B` where :math:`B` sags between gridpoints. On each interval,
    sampled at fractions :math:`\theta` (:data:`_INTERIOR`):

    1. the end bounds are clipped to what a linear, non-negative :math:`x` allows anyway,
       :math:`x_i \le \min_\theta B_\theta / (1 - \theta)` and
       :math:`x_{i+1} \le \min_\theta B_\theta / \theta` (this matters where :math:`B` is
       huge at one end, e.g. where the path's tangent vanishes);
    2. both are scaled by :math:`c = \min(1, \min_\theta B_\theta / \ell_\theta)`, with
       :math:`\ell` the chord between the clipped end bounds; then
       :math:`x_\theta \le c\,\ell_\theta \le B_\theta`.

    A gridpoint takes the smaller bound of its two intervals. The loss is of second order
    in the grid spacing.

    Returns:
        The bounds, shape (N + 1,).
    """
    ds = np.diff(grid)
    inner = (grid[:-1, None] + ds[:, None] * _INTERIOR[None, :]).ravel()
    peak = np.max(rates(path, np.concatenate([grid, inner])), axis=1)
    with np.errstate(divide="ignore"):
        bound = np.minimum(1.0 / (peak * peak), _X_CAP)
    ends = bound[: grid.size]
    between = bound[grid.size :].reshape(ds.size, _INTERIOR.size)
    left = np.minimum(ends[:-1], np.min(between / (1.0 - _INTERIOR), axis=1))
    right = np.minimum(ends[1:], np.min(between / _INTERIOR, axis=1))
    chord = left[:, None] + (right - left)[:, None] * _INTERIOR[None, :]
    factor = np.minimum(1.0, np.min(between / chord, axis=1))
    result = np.empty(grid.size)
    result[:-1] = factor * left
    result[-1] = factor[-1] * right[-1]
    result[1:-1] = np.minimum(result[1:-1], (factor * right)[:-1])
    rest = getattr(path, "rest_points", None)
    if rest is not None and rest.size:
        # (nearly) still there: exactly 0 would leave toppra's controllable set there
        # empty by round-off ([1e-16, 0])
        result[np.isin(grid, rest)] = 1e-12 * float(np.median(result))
    return result


def _joint_speed_rates(velocity: FloatArray) -> Callable[[Any, FloatArray], FloatArray]:
    """Joint speeds per unit path velocity over their limits, :math:`|q'(s)| / v`."""
    inverse = 1.0 / velocity

    def rates(path: Any, s: FloatArray) -> FloatArray:
        return np.abs(path(s, 1)) * inverse

    return rates


def _tool_speed_rates(robot: Robot, cap: float) -> Callable[[Any, FloatArray], FloatArray]:
    """Tool origin speed per unit path velocity over the cap, :math:`|J_v q'(s)| / v_{max}`."""

    def rates(path: Any, s: FloatArray) -> FloatArray:
        return (_tool_speed_factor(robot, path(s), path(s, 1)) / cap)[:, None]

    return rates


def _tool_speed_factor(robot: Robot, q: FloatArray, qd: FloatArray) -> FloatArray:
    r"""Speed of the tool frame origin for joint rates qd, :math:`|J_v(q)\,qd|`, shape (m,)."""
    model, data, frame = robot.model, robot.data, robot.tool_frame_id
    out = np.empty(len(q))
    for k in range(len(q)):
        J = pin.computeFrameJacobian(model, data, q[k], frame, pin.LOCAL_WORLD_ALIGNED)
        out[k] = np.linalg.norm(J[:3] @ qd[k])
    return out


def normalised_rows(
    a: FloatArray,
    b: FloatArray,
    c: FloatArray | None,
    a_end: FloatArray,
    b_end: FloatArray,
    c_end: FloatArray | None,
    limit: FloatArray,
) -> tuple[Any, ...]:
    r"""Canonical linear parameters for :math:`|a u + b x + c| \le` limit at interval ends.

    Each stage i gets the rows of gridpoint i (``a[i], b[i], c[i]``) and of the end of grid
    interval i (``a_end[i]``, ...; the last gridpoint repeats its own), each as two one-sided
    rows divided by :math:`\sqrt{a^2 + b^2}`. toppra's Seidel solver tests parallelism and
    feasibility with absolute tolerances (1e-10, 1e-8), so unscaled rows of a joint that
    barely moves make it report an empty controllable set on a perfectly feasible path;
    unit rows do not. Rows whose coefficients are round-off (below 1e-12 of the largest)
    become constants.

    Args:
        a: Coefficients of u at the gridpoints, shape (N + 1, m).
        b: Coefficients of x at the gridpoints, shape (N + 1, m).
        c: Constant terms at the gridpoints, shape (N + 1, m); None for zeros.
        a_end: Coefficients of the interval's u at the interval ends, shape (N, m).
        b_end: Coefficients of the interval's x_i at the interval ends, shape (N, m).
        c_end: Constant terms at the interval ends, shape (N, m); None for zeros.
        limit: Symmetric bounds, shape (m,).

    Returns:
        (a, b, c, F, g, None, None) in toppra's canonical linear form, F = identity, g = 0.
    """
    zero = np.zeros_like(a)
    c0 = zero if c is None else c
    c1 = zero[1:] if c_end is None else c_end
    a1 = np.vstack([a_end, a[-1:]])
    b1 = np.vstack([b_end, b[-1:]])
    c1 = np.vstack([c1, c0[-1:]])
    rows_a = np.hstack([a, -a, a1, -a1])
    rows_b = np.hstack([b, -b, b1, -b1])
    rows_c = np.hstack([c0 - limit, -c0 - limit, c1 - limit, -c1 - limit])
    norm = np.hypot(rows_a, rows_b)
    tiny = norm <= 1e-12 * np.max(norm)
    rows_a[tiny] = 0.0
    rows_b[tiny] = 0.0
    norm[tiny] = 1.0
    count = rows_a.shape[1]
    return (
        rows_a / norm,
        rows_b / norm,
        rows_c / norm,
        np.eye(count),
        np.zeros(count),
        None,
        None,
    )


def _torque_constraint(robot: Robot, effort: FloatArray) -> Any:
    """The joint torque constraint of toppra, fed by the robot's RNEA, without friction."""
    lib = _lib()
    model = robot.model
    data = robot.data

    def inverse_dynamics(q: FloatArray, v: FloatArray, a: FloatArray) -> FloatArray:
        return pin.rnea(model, data, q, v, a)

    return lib.TorqueConstraint(
        inverse_dynamics,
        np.column_stack([-effort, effort]),
        np.zeros(robot.dof),
        discretization_scheme=lib.Collocation,
    )


# ------------------------------------------------------------------------------ paths


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
        first = _derivative(self.coefficients)
        return first, _derivative(first)

    @cached_property
    def native(self) -> Any:
        """The path as a toppra ``AbstractGeometricPath``."""
        return _lib().PolynomialPath(self)

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
            derivative = self.derivatives[order]
            left = np.abs(_polyval_local(derivative[:-1], lengths))
            right = np.abs(derivative[1:, 0, :])
            still &= np.max(np.maximum(left, right), axis=1) <= 1e-9 * scale
        return self.knots[1:-1][still]

    @cached_property
    def length(self) -> float:
        """Sum of the segments' joint-space chords [rad or m] (a length estimate)."""
        ends = _polyval_local(self.coefficients, np.diff(self.knots))
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


def _polyval_local(coefficients: FloatArray, tau: FloatArray) -> FloatArray:
    """Each segment's polynomial at its own local coordinate, shape (m, n) for tau (m,)."""
    result = coefficients[:, -1, :].copy()
    for i in range(coefficients.shape[1] - 2, -1, -1):
        result = result * tau[:, None] + coefficients[:, i, :]
    return result


def _segments(knots: FloatArray, s: FloatArray) -> NDArray[np.intp]:
    """Segment of each path position (a position on a knot: the segment that starts there)."""
    return np.clip(np.searchsorted(knots, s, side="right") - 1, 0, knots.size - 2)


def _polyval_grid(rows: FloatArray, sigma: FloatArray) -> FloatArray:
    """Polynomials ``rows`` (shape (N, d + 1, n)) at local coordinates ``sigma`` (N, P).

    Returns:
        Values, shape (N, P, n).
    """
    x = sigma[:, :, None]
    result = np.broadcast_to(rows[:, None, -1, :], (*sigma.shape, rows.shape[2]))
    for i in range(rows.shape[1] - 2, -1, -1):
        result = result * x + rows[:, None, i, :]
    return np.asarray(result)


def _derivative(coefficients: FloatArray) -> FloatArray:
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
    first = _derivative(coefficients)
    second = _derivative(first)
    left = _polyval_local(second[:-1], np.diff(knots)[:-1])
    right = second[1:, 0, :]
    scale = np.max(np.abs(right)) + np.max(np.abs(left)) + 1e-300
    at = np.flatnonzero(np.max(np.abs(left - right), axis=1) > 1e-9 * scale)
    return knots[at + 1], coefficients[at + 1, 0, :], first[at + 1, 0, :], left[at]


def jump_rows(
    path: Any, gridpoints: FloatArray
) -> list[tuple[int, float, FloatArray, FloatArray, FloatArray]]:
    """Grid intervals that end on a curvature jump of the path.

    Returns:
        (interval index, its length, q, q', left q'') for each such interval.
    """
    jumps = getattr(path, "curvature_jumps", None)
    if jumps is None or jumps[0].size == 0:
        return []
    grid = np.asarray(gridpoints)
    index = np.searchsorted(grid, jumps[0])
    rows = []
    for k, i in enumerate(index):
        if 0 < i < grid.size and grid[i] == jumps[0][k]:
            rows.append((int(i - 1), float(grid[i] - grid[i - 1]), *(x[k] for x in jumps[1:])))
    return rows


def _position_extremes(
    knots: FloatArray, coefficients: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Exact lowest and highest value of each joint of a piecewise polynomial.

    Candidates are each segment's ends and the real roots of its derivative (closed form up
    to cubics, companion matrices beyond).

    Returns:
        (low, s_low, high, s_high), each shape (n,): the values and where they occur.
    """
    m, terms, n = coefficients.shape
    lengths = np.diff(knots)[:, None]
    slope = _derivative(coefficients)
    degree = terms - 2
    candidates = [np.zeros((m, n)), np.broadcast_to(lengths, (m, n))]
    with np.errstate(divide="ignore", invalid="ignore"):
        if degree == 1:
            candidates.append(-slope[:, 0, :] / slope[:, 1, :])
        elif degree == 2:
            a, b, c = slope[:, 2, :], slope[:, 1, :], slope[:, 0, :]
            root = np.sqrt(b * b - 4.0 * a * c)
            q = -0.5 * (b + np.copysign(root, b))
            candidates += [q / a, c / q, -c / b]
        elif degree > 2:
            flat = np.moveaxis(slope, 1, 2).reshape(m * n, degree + 1)
            roots = np.full((m * n, degree), np.nan)
            # each derivative's true degree (padded pieces end in zeros); roots per degree
            nonzero = flat != 0.0
            actual = np.where(nonzero.any(axis=1), degree - np.argmax(nonzero[:, ::-1], axis=1), 0)
            for d in np.unique(actual[actual > 0]):
                rows = np.flatnonzero(actual == d)
                companion = np.zeros((rows.size, d, d))
                companion[:, 1:, :-1] = np.eye(d - 1)
                companion[:, :, -1] = -flat[rows, :d] / flat[rows, d : d + 1]
                values = np.linalg.eigvals(companion)
                real = np.abs(values.imag) <= 1e-7 * (1.0 + np.abs(values.real))
                roots[rows, :d] = np.where(real, values.real, np.nan)
            candidates += list(np.moveaxis(roots.reshape(m, n, degree), 2, 0))
    tau = np.stack(candidates)
    tau = np.clip(np.where(np.isfinite(tau), tau, 0.0), 0.0, lengths[None])
    values = np.broadcast_to(coefficients[None, :, -1, :], tau.shape).copy()
    for i in range(terms - 2, -1, -1):
        values = values * tau + coefficients[None, :, i, :]
    values = values.reshape(-1, n)
    where = (tau + knots[None, :-1, None]).reshape(-1, n)
    low_at = np.argmin(values, axis=0)
    high_at = np.argmax(values, axis=0)
    cols = np.arange(n)
    return values[low_at, cols], where[low_at, cols], values[high_at, cols], where[high_at, cols]


def _spline_within(path: GeometricPath, limits: JointLimits) -> bool:
    """Whether a cubic path through waypoints within the limits stays within them.

    The waypoints are the segment ends, so only the interior extrema (the roots of each
    segment's quadratic derivative) need checking; the checker's allowance (1e-9 of each
    joint's range) counts as within.
    """
    c0, c1, c2, c3 = (path.coefficients[:, i, :] for i in range(4))
    h = np.diff(path.knots)[:, None]
    a = 3.0 * c3
    b = 2.0 * c2
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (b + np.copysign(np.sqrt(b * b - 4.0 * a * c1), b))
        roots = np.stack([q / a, c1 / q])  # both roots; -c1/b when a == 0
    roots = np.where((roots > 0.0) & (roots < h), roots, 0.0)  # NaN fails both: 0
    values = ((c3 * roots + c2) * roots + c1) * roots + c0
    slack = 1e-9 * (limits.upper - limits.lower)
    return bool(np.all(values >= limits.lower - slack) and np.all(values <= limits.upper + slack))


def _position_excess(path: GeometricPath, limits: JointLimits) -> JointLimitError | None:
    """The error for the joint whose path goes furthest beyond its position limits, if any.

    The checker's allowance (1e-9 of each joint's range) counts as within.
    """
    slack = 1e-9 * (limits.upper - limits.lower)
    coeffs = path.coefficients
    if coeffs.shape[1] == 4:  # a cubic lies in the hull of its Bezier control points
        h = np.diff(path.knots)[:, None]
        c0, c1, c2, c3 = (coeffs[:, i, :] for i in range(4))
        p1 = c0 + c1 * h / 3.0
        p2 = p1 + (c1 * h + c2 * h * h) / 3.0
        p3 = c0 + ((c3 * h + c2) * h + c1) * h
        hull = np.stack([c0, p1, p2, p3])
        if np.all(hull >= limits.lower - slack) and np.all(hull <= limits.upper + slack):
            return None
    low, s_low, high, s_high = _position_extremes(path.knots, coeffs)
    below = limits.lower - low
    above = high - limits.upper
    excess = np.maximum(below, above) - slack
    j = int(np.argmax(excess))
    if excess[j] <= 0.0:
        return None
    lower_side = below[j] >= above[j]
    where = s_low[j] if lower_side else s_high[j]
    return JointLimitError(
        limits.names[j],
        low[j] if lower_side else high[j],
        limits.lower[j],
        limits.upper[j],
        unit=limits.unit("position", j),
        context=f"the {path.kind} path at s = {where:.6g} {path.unit}",
    )


def _check_path_positions(path: GeometricPath, limits: JointLimits) -> None:
    """Raise for the joint whose path goes furthest beyond its position limits.

    Raises:
        JointLimitError: Naming the joint, the value and the path position.
    """
    error = _position_excess(path, limits)
    if error is not None:
        raise error


def _check_tangent(path: GeometricPath, limits: JointLimits) -> None:
    """Raise when the path's tangent jumps at a knot (a corner: passable only at rest)."""
    coeffs = path.coefficients
    if coeffs.shape[0] < 2:
        return
    first = _derivative(coeffs)
    left = _polyval_local(first[:-1], np.diff(path.knots)[:-1])
    right = first[1:, 0, :]
    typical = path.length / (path.knots[-1] - path.knots[0])  # mean joint-space speed
    scale = max(float(np.max(np.abs(first[:, 0, :]))), float(np.max(np.abs(left))), typical)
    jump = np.abs(left - right)
    k, j = np.unravel_index(int(np.argmax(jump)), jump.shape)
    if jump[k, j] > 1e-6 * scale:
        raise InvalidInputError(
            f"the path's tangent jumps at s = {path.knots[k + 1]:.6g} {path.unit}: joint "
            f"{limits.names[j]!r} goes from {left[k, j]:.6g} to {right[k, j]:.6g} per unit s. "
            "A corner can only be passed at rest; split the path there and retime the pieces",
            name="path",
        )


# -------------------------------------------------------------------- exact conversion


class _TimeLaw:
    """The constant-acceleration time law of a solved grid: s(t) quadratic per interval.

    Attributes:
        grid: Gridpoints s_i [path units], shape (N + 1,).
        sd: Path velocities at the gridpoints [path units/s], shape (N + 1,).
        u: Path acceleration on each interval [path units/s^2], shape (N,).
        t: Time of each gridpoint [s], shape (N + 1,).
    """

    def __init__(self, grid: FloatArray, sd: FloatArray) -> None:
        self.grid = grid
        self.sd = sd
        ds = np.diff(grid)
        x = sd * sd
        self.u = (x[1:] - x[:-1]) / (2.0 * ds)
        self.t = np.concatenate([[0.0], np.cumsum(2.0 * ds / (sd[:-1] + sd[1:]))])

    def locate(self, s: FloatArray) -> tuple[NDArray[np.intp], FloatArray]:
        """Grid interval of each path position and the time into it [s]."""
        i = np.clip(np.searchsorted(self.grid, s, side="right") - 1, 0, self.grid.size - 2)
        d = np.maximum(s - self.grid[i], 0.0)
        v0 = self.sd[i]
        denominator = v0 + np.sqrt(np.maximum(v0 * v0 + 2.0 * self.u[i] * d, 0.0))
        tau = np.divide(2.0 * d, denominator, out=np.zeros_like(d), where=denominator > 0.0)
        return i, tau

    def time_at(self, s: FloatArray) -> FloatArray:
        """Time at which each path position is reached [s]."""
        s = np.asarray(s, dtype=float)
        index = np.minimum(np.searchsorted(self.grid, s), self.grid.size - 1)
        if np.all(self.grid[index] == s):  # gridpoints (knots, path ends): no root needed
            return self.t[index]
        i, tau = self.locate(s)
        return np.clip(self.t[i] + tau, 0.0, self.t[-1])


def compose(
    knots: ArrayLike, coefficients: ArrayLike, grid: ArrayLike, sd: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    r"""The exact q(t) of a piecewise polynomial path under toppra's constant-acceleration law.

    On grid interval i the path acceleration is :math:`u_i = (\dot s_{i+1}^2 - \dot s_i^2) /
    (2 (s_{i+1} - s_i))` (toppra's ``ParametrizeConstAccel``), so :math:`s(t)` is quadratic;
    substituting it into the path's polynomials gives polynomials in t of twice their
    degree, one per piece between the grid times and the times the path's knots are
    crossed (none when every knot is a gridpoint).

    Args:
        knots: Path segment boundaries [path units], shape (m + 1,).
        coefficients: Path coefficients, shape (m, d + 1, n), ascending local powers.
        grid: Gridpoints [path units], shape (N + 1,), from knots[0] to knots[-1].
        sd: Path velocities at the gridpoints [path units/s], shape (N + 1,), >= 0, no two
            consecutive zeros.

    Returns:
        (breakpoints [s], shape (K + 1,); coefficients, shape (K, 2 d + 1, n)) for
        :class:`~planners.trajectory.Trajectory`.
    """
    law = _TimeLaw(np.asarray(grid, dtype=float), np.asarray(sd, dtype=float))
    return _compose(np.asarray(knots, dtype=float), np.asarray(coefficients, dtype=float), law)


def _compose(
    knots: FloatArray,
    coefficients: FloatArray,
    law: _TimeLaw,
    segment: NDArray[np.intp] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """:func:`compose`, faster when every knot is a gridpoint.

    Args:
        knots: As for :func:`compose`.
        coefficients: As for :func:`compose`.
        law: The time law of the grid.
        segment: The path segment of each grid interval, shape (N,), when every knot is a
            gridpoint (the pieces are then the grid intervals); None to find the pieces.
    """
    grid, sd, u, t_grid = law.grid, law.sd, law.u, law.t
    count = grid.size - 1
    interval = np.arange(count)
    s_a, v_a, t_a = grid[:-1], sd[:-1], t_grid[:-1]
    inner = knots[1:-1]
    if segment is None and inner.size:  # pieces also start where a knot is crossed
        i_k, tau_k = law.locate(inner)
        span = grid[i_k + 1] - grid[i_k]
        h_k = t_grid[i_k + 1] - t_grid[i_k]
        keep = (
            (inner - grid[i_k] > 1e-12 * span)
            & (grid[i_k + 1] - inner > 1e-12 * span)
            & (tau_k > 1e-12 * h_k)
            & (tau_k < (1.0 - 1e-12) * h_k)
        )
        if np.any(keep):
            i_k, tau_k = i_k[keep], tau_k[keep]
            order = np.argsort(np.concatenate([grid[:-1], inner[keep]]), kind="stable")
            interval = np.concatenate([interval, i_k])[order]
            s_a = np.concatenate([s_a, inner[keep]])[order]
            v_a = np.concatenate([v_a, sd[i_k] + u[i_k] * tau_k])[order]
            t_a = np.concatenate([t_a, t_grid[i_k] + tau_k])[order]
    if segment is None or segment.size != s_a.size:
        segment = _segments(knots, s_a)
    # sigma(tau) = a0 + a1 tau + a2 tau^2, the position in the segment; Horner in sigma.
    a0 = (s_a - knots[segment])[:, None, None]
    a1 = v_a[:, None, None]
    a2 = 0.5 * u[interval][:, None, None]
    rows = coefficients[segment]
    degree = rows.shape[1] - 1
    result = rows[:, degree : degree + 1, :]
    for i in range(degree - 1, -1, -1):
        width = result.shape[1]
        grown = np.empty((result.shape[0], width + 2, result.shape[2]))
        grown[:, :width, :] = result * a0
        grown[:, width:, :] = 0.0
        grown[:, 1 : width + 1, :] += result * a1
        grown[:, 2:, :] += result * a2
        grown[:, 0, :] += rows[:, i, :]
        result = grown
    return np.append(t_a, t_grid[-1]), result


# ---------------------------------------------------------------------------- problem


@dataclass(frozen=True, eq=False)
class ToppraProblem:
    """A validated TOPPRA problem, ready for :meth:`Toppra.solve` and open to inspection.

    Attributes:
        path: The geometric path.
        limits: The limits the result must respect.
        grid: Gridpoints [path units], shape (N + 1,); every knot of the path is one.
        sd_start: Path velocity at the start [path units/s], >= 0.
        sd_end: Path velocity at the end [path units/s], >= 0.
        robot: The robot (torque limits, tool speed cap), or None.
        torque: Whether the joint torque limits (``limits.effort``) apply.
        tool_speed: Cap on the tool frame origin's speed [m/s], or None.
        phases: Named windows of the result as path positions (name, s_start, s_end).
        segment: The path segment of each grid interval, shape (N,).
    """

    path: GeometricPath
    limits: JointLimits
    grid: FloatArray
    sd_start: float
    sd_end: float
    robot: Robot | None
    torque: bool
    tool_speed: float | None
    phases: tuple[tuple[str, float, float], ...]
    segment: NDArray[np.intp]

    def constraints(self, scale: dict[str, float] | None = None) -> list[Any]:
        """The toppra constraints, each rate limit multiplied by its factor in ``scale``.

        Args:
            scale: Factor per quantity (``"velocity"``, ``"acceleration"``, ``"torque"``,
                ``"tool speed"``); 1 - :data:`MARGIN` for those not given.
        """
        factor = _initial_scale(self)
        factor.update(scale or {})
        lib = _lib()
        limits = self.limits
        constraints = [
            lib.SpeedConstraint(_joint_speed_rates(limits.velocity * factor["velocity"]), limits.n),
            lib.AccelerationConstraint(limits.acceleration * factor["acceleration"]),
        ]
        if self.torque and self.robot is not None:
            constraints.append(_torque_constraint(self.robot, limits.effort * factor["torque"]))
        if self.tool_speed is not None and self.robot is not None:
            cap = self.tool_speed * factor["tool speed"]
            constraints.append(lib.SpeedConstraint(_tool_speed_rates(self.robot, cap), limits.n))
        return constraints


def _initial_scale(problem: ToppraProblem) -> dict[str, float]:
    """Every limited quantity of the problem with the factor 1 - MARGIN."""
    names = ["velocity", "acceleration"]
    if problem.torque:
        names.append("torque")
    if problem.tool_speed is not None:
        names.append("tool speed")
    return dict.fromkeys(names, 1.0 - MARGIN)


class Toppra:
    """Time-optimal path parametrisation with TOPPRA; the ``plan(problem)`` face.

    Args:
        gridpoints: Number of grid intervals N along the path (the grid holds N + 1
            gridpoints: toppra's N stages). By default one per 0.02 rad (or m) of
            joint-space path length, clipped to [100, 400]. Intervals are spread over the
            path's segments in proportion to their length, so every knot is a gridpoint (a
            path of more than N segments gets one interval per segment).
        torque: Also respect the joint torque limits (``limits.effort``), with inverse
            dynamics by the robot's RNEA; needs a robot.
        tool_speed: Cap on the speed of the tool frame origin [m/s], or None; needs a robot.
        start_path_velocity: Default path velocity at the start for
            :meth:`time_parametrize` [path units/s], >= 0.
        end_path_velocity: Default path velocity at the end for :meth:`time_parametrize`
            [path units/s], >= 0.

    Path units: a waypoint path is parametrised by cumulative chord length in joint space
    [rad or m] (a path velocity of 1 moves the joints at 1 rad/s along the chords), a
    Trajectory path by its own time [s] (a path velocity of 1 replays it at its own pace).

    Raises:
        InvalidInputError: A gridpoint count below 2 or above MAX_GRIDPOINTS, a tool speed
            <= 0 or above MAX_TOOL_SPEED, path velocities below 0 or above 1e8, a torque flag
            that is not a bool.
    """

    #: Name recorded in trajectory metadata.
    name = "toppra"

    def __init__(
        self,
        gridpoints: int | None = None,
        torque: bool = False,
        tool_speed: float | None = None,
        start_path_velocity: float = 0.0,
        end_path_velocity: float = 0.0,
    ) -> None:
        self.gridpoints = (
            None
            if gridpoints is None
            else as_count(gridpoints, "gridpoints", 2, maximum=MAX_GRIDPOINTS)
        )
        self.torque = as_flag(torque, "torque")
        self.tool_speed = (
            None
            if tool_speed is None
            else as_positive(tool_speed, "tool_speed", "m/s", maximum=MAX_TOOL_SPEED)
        )
        self.start_path_velocity = _path_velocity(start_path_velocity, "start_path_velocity")
        self.end_path_velocity = _path_velocity(end_path_velocity, "end_path_velocity")

    def __repr__(self) -> str:
        return (
            f"Toppra(gridpoints={self.gridpoints}, torque={self.torque}, "
            f"tool_speed={self.tool_speed}, start_path_velocity={self.start_path_velocity}, "
            f"end_path_velocity={self.end_path_velocity})"
        )

    # ---------------------------------------------------------------------- faces

    def plan(self, problem: Waypoints | PointToPoint) -> Trajectory:
        """Plan a problem time-optimally along a fixed geometric path.

        * :class:`problems.Waypoints`: a not-a-knot cubic spline through the waypoints
          (s = cumulative chord length), at rest at both ends, with phases ``segment 1`` ..
          ``segment k-1`` between the waypoints. Where that spline would leave the joint
          limits, a shape-preserving PCHIP cubic through the same waypoints is used
          (``metadata["path"]`` says which).
        * :class:`problems.PointToPoint`: the straight joint-space line, phase ``move``. A
          start or goal velocity along the line is honoured as a path velocity.

        Raises:
            InvalidInputError: Another problem type; fixed segment durations or a fixed
                duration (TOPPRA chooses the timing); a boundary velocity off the line, a
                prescribed non-zero boundary acceleration, a goal equal to the start; a
                planner built with non-zero default path velocities.
            InfeasibleError, SolverError: As for :meth:`solve`.
        """
        started = time.perf_counter()
        if isinstance(problem, Waypoints):
            built = self._build_waypoints(problem)
        elif isinstance(problem, PointToPoint):
            built = self._build_line(problem)
        else:
            raise InvalidInputError(
                f"Toppra plans a problems.Waypoints or a problems.PointToPoint, got "
                f"{type(problem).__name__}; retime other paths with time_parametrize",
                name="problem",
            )
        return self._solve(built, started)

    def time_parametrize(
        self,
        path: ArrayLike | Trajectory,
        limits: JointLimits,
        *,
        robot: Robot | None = None,
        sd_start: float | None = None,
        sd_end: float | None = None,
    ) -> Trajectory:
        """Retime a geometric path as fast as the limits allow.

        Args:
            path: Waypoints [rad or m], shape (k, n), k >= 2 (the spline of :meth:`plan`,
                s = cumulative chord length [rad]), or a
                :class:`~planners.trajectory.Trajectory` whose positions over its own time
                are the path (s = its time [s]; its phases move to the new times).
            limits: Joint limits to respect; the path must stay within the position limits.
            robot: The robot; needed for torque limits or a tool speed cap.
            sd_start: Path velocity at the start [path units/s], >= 0; the planner's
                ``start_path_velocity`` when None.
            sd_end: Path velocity at the end [path units/s], >= 0; the planner's
                ``end_path_velocity`` when None.

        Returns:
            The retimed trajectory: exact piecewise polynomials (see :func:`compose`).

        Raises:
            InvalidInputError: A malformed path or limits, a path with a corner, a missing
                robot, a negative path velocity.
            JointLimitError: The path leaves the position limits (joint and s named).
            InfeasibleError, SolverError: As for :meth:`solve`.
        """
        started = time.perf_counter()
        built = self.build(path, limits, robot=robot, sd_start=sd_start, sd_end=sd_end)
        return self._solve(built, started)

    def build(
        self,
        path: ArrayLike | Trajectory,
        limits: JointLimits,
        *,
        robot: Robot | None = None,
        sd_start: float | None = None,
        sd_end: float | None = None,
    ) -> ToppraProblem:
        """Validate a path and set up the problem that :meth:`solve` solves.

        Arguments and errors as for :meth:`time_parametrize` (which is ``solve(build(...))``).
        """
        if not isinstance(limits, JointLimits):
            raise InvalidInputError(
                f"limits must be a robots.JointLimits, got {type(limits).__name__}",
                name="limits",
            )
        start = (
            self.start_path_velocity if sd_start is None else _path_velocity(sd_start, "sd_start")
        )
        end = self.end_path_velocity if sd_end is None else _path_velocity(sd_end, "sd_end")
        if isinstance(path, Trajectory):
            if path.dof != limits.n:
                raise InvalidInputError(
                    f"the path has {path.dof} joints, the limits {limits.n}", name="path"
                )
            geometric = GeometricPath.from_trajectory(path)
            if not np.any(geometric.coefficients[:, 1:, :]):
                raise InvalidInputError(
                    "the path trajectory stands still: there is no path to parametrise",
                    name="path",
                )
            _check_tangent(geometric, limits)
            _check_path_positions(geometric, limits)
            phases = tuple((p.name, p.t_start, p.t_end) for p in path.phases)
            return self._assemble(geometric, limits, robot, start, end, phases)
        points = as_array(path, "path", (None, limits.n))
        if points.shape[0] < 2:
            raise InvalidInputError(
                f"path needs at least 2 waypoints, got {points.shape[0]}", name="path"
            )
        for k, q in enumerate(points):
            limits.check_position(q, tolerance=1e-9, context=f"path waypoint {k}")
        geometric, _ = _waypoint_path(points, limits)
        return self._assemble(geometric, limits, robot, start, end, ())

    def solve(self, problem: ToppraProblem) -> Trajectory:
        """Solve a built problem.

        Raises:
            InfeasibleError: Gravity alone breaks a torque limit on the path (joint and s
                named); the start or end path velocity is beyond what the limits allow (the
                requested and the largest feasible value named); the controllable set is
                empty at a gridpoint (index and s named).
            SolverError: toppra's forward pass failed, or a motion with a moving start or
                end still exceeds a limit between gridpoints after the re-solves (more
                gridpoints help).
        """
        return self._solve(problem, time.perf_counter())

    # ------------------------------------------------------------------ building

    def _build_waypoints(self, problem: Waypoints) -> ToppraProblem:
        self._require_rest("Waypoints")
        if problem.segment_durations is not None:
            raise InvalidInputError(
                "Toppra chooses the timing itself; a Waypoints problem with "
                "segment_durations cannot be honoured (leave them None, or use "
                "planners.ViaPoints)",
                name="segment_durations",
            )
        problem.require_motion(  # segment_durations are None here: Toppra cannot hold still
            self.name,
            reason="so there is no path to parametrise",
            remedy="give segment_durations to hold still and plan with planners.ViaPoints",
        )
        limits = _limits_of(problem)
        path, index = _waypoint_path(np.asarray(problem.waypoints, dtype=float), limits)
        s = path.knots[index]
        phases = tuple((f"segment {k + 1}", s[k], s[k + 1]) for k in range(s.size - 1))
        return self._assemble(path, limits, problem.robot, 0.0, 0.0, phases)

    def _build_line(self, problem: PointToPoint) -> ToppraProblem:
        self._require_rest("PointToPoint")
        if problem.duration is not None:
            raise InvalidInputError(
                "Toppra plans the fastest motion; a PointToPoint with a fixed duration "
                "cannot be honoured (leave duration None, or use a time scaling)",
                name="duration",
            )
        for label, value in (("qdd_start", problem.qdd_start), ("qdd_goal", problem.qdd_goal)):
            if value is not None and np.any(np.asarray(value) != 0.0):
                raise InvalidInputError(
                    f"Toppra cannot prescribe boundary accelerations; {label} = "
                    f"{np.round(np.asarray(value), 6).tolist()} is not zero",
                    name=label,
                )
        # the rule of every planner, rest to rest; Toppra itself takes no duration
        problem.require_motion(
            self.name, "give a duration to hold still, and plan it with a time scaling"
        )
        if problem.still:  # with a boundary velocity: no straight line to move along
            raise still_error(
                self.name,
                reason="so there is no straight line to move along",
                remedy="plan it with Ruckig or a time scaling",
            )
        q0 = np.asarray(problem.q_start, dtype=float)
        q1 = np.asarray(problem.q_goal, dtype=float)
        length = float(np.linalg.norm(q1 - q0))
        direction = (q1 - q0) / length
        speeds = []
        for label, value in (("qd_start", problem.qd_start), ("qd_goal", problem.qd_goal)):
            qd = np.zeros(q0.size) if value is None else np.asarray(value, dtype=float)
            along = float(qd @ direction)
            off = float(np.linalg.norm(qd - along * direction))
            if along < 0.0 or off > 1e-9 * max(1.0, abs(along)):
                raise InvalidInputError(
                    f"Toppra moves along the straight line from q_start to q_goal; {label} = "
                    f"{np.round(qd, 6).tolist()} does not point forwards along it",
                    name=label,
                )
            speeds.append(along)
        path = GeometricPath.line(q0, q1)
        limits = _limits_of(problem)
        return self._assemble(
            path, limits, problem.robot, speeds[0], speeds[1], (("move", 0.0, length),)
        )

    def _require_rest(self, what: str) -> None:
        if self.start_path_velocity != 0.0 or self.end_path_velocity != 0.0:
            raise InvalidInputError(
                f"a {what} problem prescribes its own boundary velocities; the planner's "
                "start_path_velocity and end_path_velocity apply to time_parametrize only",
                name="start_path_velocity",
            )

    def _assemble(
        self,
        path: GeometricPath,
        limits: JointLimits,
        robot: Robot | None,
        sd_start: float,
        sd_end: float,
        phases: tuple[tuple[str, float, float], ...],
    ) -> ToppraProblem:
        if (self.torque or self.tool_speed is not None) and not isinstance(robot, Robot):
            wanted = "torque limits need" if self.torque else "a tool speed cap needs"
            raise InvalidInputError(
                f"{wanted} the robot: pass robot=robots.load(...)", name="robot"
            )
        if robot is not None and robot.dof != limits.n:
            raise InvalidInputError(
                f"robot {robot.name!r} has {robot.dof} joints, the limits {limits.n}",
                name="robot",
            )
        grid = _grid(path, self.gridpoints)
        return ToppraProblem(
            path=path,
            limits=limits,
            grid=grid,
            sd_start=float(sd_start),
            sd_end=float(sd_end),
            robot=robot,
            torque=self.torque,
            tool_speed=self.tool_speed,
            phases=phases,
            segment=_segments(path.knots, grid[:-1]),
        )

    # ------------------------------------------------------------------- solving

    def _solve(self, problem: ToppraProblem, started: float) -> Trajectory:
        lib = _lib()
        path = problem.path
        if problem.torque:
            _check_gravity(problem)
        scale = _initial_scale(problem)
        if problem.sd_end > 0.0:
            _check_end_velocity(problem, scale)
        moving = problem.sd_start > 0.0 or problem.sd_end > 0.0
        # toppra solves on a path at least one path unit long (see _STRETCH_BELOW)
        stretch = _stretch(path)
        native = path.native if stretch == 1.0 else path.stretched(stretch).native
        for attempt in range(RETRIES + 1):
            instance = lib.TOPPRA(problem.constraints(scale), native, problem.grid * stretch)
            _, sd, _, K = instance.compute_parameterization(
                problem.sd_start * stretch, problem.sd_end * stretch, return_data=True
            )
            if sd is not None:  # back to the path's own units: sd / c, x = sd^2 / c^2
                sd = np.asarray(sd, dtype=float) / stretch
            if K is not None:
                K = np.asarray(K, dtype=float) / stretch**2
            if sd is None or instance.problem_data.return_code != lib.Ok:
                _raise_failure(problem, instance, sd, K)
            if problem.sd_start**2 > float(K[0, 1]) * (1.0 + 1e-9):
                # toppra lets a start up to 1e-5 (in sd^2) beyond its controllable set pass
                _raise_failure(problem, instance, None, K)
            law = _TimeLaw(problem.grid, np.asarray(sd, dtype=float))
            ratios, after, slowdown, over = _verify(problem, law)
            if max(ratios.values()) <= _TARGET:
                break
            if attempt < RETRIES and slowdown < 1.0 / (1.0 + _REFINE_ABOVE):
                # a marked excess between gridpoints: refine the grid there and solve again
                problem = _refined(problem, over)
                continue
            if not moving:
                break  # slowed down below
            if attempt == RETRIES:
                name = max(ratios, key=ratios.__getitem__)
                raise SolverError(
                    "toppra",
                    "limit exceeded between gridpoints",
                    iterations=attempt + 1,
                    detail=(
                        f"after {attempt + 1} solves the {name} still reaches "
                        f"{ratios[name]:.6g} x its limit between gridpoints; use more "
                        f"gridpoints (now {problem.grid.size - 1})"
                    ),
                )
            for name, ratio in ratios.items():
                if ratio > _TARGET:
                    scale[name] *= _TARGET / ratio
        if slowdown < 1.0:  # rest to rest: slow the whole motion down just enough
            law = _TimeLaw(problem.grid, law.sd * slowdown)
            ratios = after
        floor = float(law.t[-1]) / MIN_DURATION * (1.0 - 1e-12)  # not a rounding below
        if not moving and floor < 1.0:
            # a tiny move lasts MIN_DURATION, the shortest duration any planner takes (a
            # slower rest-to-rest motion only lowers every speed and acceleration)
            law = _TimeLaw(problem.grid, law.sd * floor)
            ratios = _verify(problem, law)[0]
            slowdown = min(slowdown, 1.0) * floor
        breakpoints, coefficients = _compose(path.knots, path.coefficients, law, problem.segment)
        phase_s = np.array([[p[1], p[2]] for p in problem.phases], dtype=float).reshape(-1, 2)
        phase_t = law.time_at(phase_s.ravel()).reshape(-1, 2)
        traj = Trajectory(
            breakpoints,
            coefficients,
            joint_names=problem.limits.names,
            phases=[
                Phase(p[0], t0, max(t0, t1))
                for p, (t0, t1) in zip(problem.phases, phase_t, strict=True)
            ],
            metadata={"native": lib.ConstAccelOutput(path.native, problem.grid, law.sd)},
        )
        return stamp(
            traj,
            self.name,
            started,
            gridpoints=problem.grid.size - 1,
            path=path.kind,
            path_unit=path.unit,
            sd_start=problem.sd_start,
            sd_end=problem.sd_end,
            margin={name: 1.0 - factor for name, factor in scale.items()},
            limit_ratio=ratios,
            slowdown=1.0 / slowdown,
            solves=attempt + 1,
            grid=problem.grid,
            grid_times=law.t,
            path_velocity=law.sd,
            controllable_sets=K,
        )


# ---------------------------------------------------------------------------- helpers


def _stretch(path: GeometricPath) -> float:
    """Factor c >= 1 on the path parameter that brings a short path's numbers to toppra's scale.

    toppra's Seidel solver tests feasibility with absolute tolerances (1e-10, 1e-8; see
    :func:`normalised_rows`) and caps values at 1e8 (``toppra.constants.VERYLARGE``). Along
    a path of length L at a path acceleration bound a, the squared path velocity is about
    a L in the middle and 2 a ds near a rest end (ds = L / N the grid step): on a Sawyer
    line 1e-9 rad long with 100 intervals that is about 1.4e-10, and toppra called the
    controllable set empty on moves of 1e-11 to 1e-9 rad. In the parameter c s squared path
    velocities grow by c^2 and path accelerations by c; c = 1 / sqrt(L) makes the squared
    path velocities of order a (a L c^2 = a, 2 a / N at the ends) and keeps the path
    accelerations, a / sqrt(L), below the cap for any L above STILL_TOLERANCE (c = 1 / L
    instead pushed them into the cap, and tiny moves came out 100 times slower than
    optimal). Paths at least one unit long are solved as they are.
    """
    span = float(path.knots[-1] - path.knots[0])
    return 1.0 / math.sqrt(span) if 0.0 < span < _STRETCH_BELOW else 1.0


def _refined(problem: ToppraProblem, intervals: NDArray[np.intp]) -> ToppraProblem:
    """The problem with each of the given grid intervals split into four."""
    grid = problem.grid
    inner = grid[intervals, None] + np.diff(grid)[intervals, None] * np.array([0.25, 0.5, 0.75])
    finer = np.sort(np.concatenate([grid, inner.ravel()]))
    return dataclasses.replace(
        problem, grid=finer, segment=_segments(problem.path.knots, finer[:-1])
    )


def _path_velocity(value: float, name: str) -> float:
    """A path velocity [path units/s] in [0, sqrt(_X_CAP)].

    toppra moves forwards only, and no squared path velocity above :data:`_X_CAP` is offered
    to it.
    """
    return as_number(value, name, "path units/s", minimum=0.0, maximum=math.sqrt(_X_CAP))


def _limits_of(problem: Waypoints | PointToPoint) -> JointLimits:
    limits = problem.limits
    if not isinstance(limits, JointLimits):  # resolved by the problem; never None
        raise InvalidInputError("the problem has no joint limits", name="limits")
    return limits


def _waypoint_path(
    points: FloatArray, limits: JointLimits
) -> tuple[GeometricPath, NDArray[np.intp]]:
    """The spline through waypoints, or the PCHIP cubic where the spline leaves the limits.

    Returns:
        The path and, for each given waypoint, the index of its knot (a waypoint equal to
        its predecessor shares its knot).

    Raises:
        InvalidInputError: Every waypoint is the same configuration.
    """
    # a waypoint equal to its predecessor (the rule of problems.PointToPoint.still) is merged
    step = np.max(np.abs(np.diff(points, axis=0)), axis=1)
    new = np.concatenate([[True], step > STILL_TOLERANCE])
    if np.count_nonzero(new) < 2:
        raise InvalidInputError(
            "every waypoint is the same configuration: there is no path to parametrise",
            name="waypoints",
        )
    distinct = points[new]
    path = GeometricPath.spline(distinct)
    if not _spline_within(path, limits):
        path = GeometricPath.pchip(distinct)
        _check_path_positions(path, limits)  # holds by construction; cheap to confirm
    return path, np.cumsum(new) - 1


def _grid(path: GeometricPath, intervals: int | None) -> FloatArray:
    """About N grid intervals, spread over the path's segments by their length.

    Every knot is a gridpoint (each segment gets at least one interval): no piece of the
    output straddles a knot, and where the path's curvature jumps at a knot the acceleration
    and torque constraints see both sides of the jump.
    """
    knots = path.knots
    if intervals is None:
        intervals = int(np.clip(math.ceil(path.length / _GRID_STEP), _MIN_GRID, _MAX_GRID))
    lengths = np.diff(knots)
    if lengths.size == 1:
        return np.linspace(knots[0], knots[-1], intervals + 1)
    share = intervals * lengths / (knots[-1] - knots[0])
    counts = np.maximum(np.floor(share).astype(np.intp), 1)
    spare = intervals - int(counts.sum())
    if spare > 0:
        counts[np.argsort(counts - share)[:spare]] += 1
    if path.rest_points.size:  # a dwell between two rest points needs a point inside
        dwell = np.isin(knots[:-1], path.rest_points) & np.isin(knots[1:], path.rest_points)
        counts[dwell] = np.maximum(counts[dwell], 2)
    segment = np.repeat(np.arange(lengths.size), counts)
    offset = np.arange(segment.size) - np.repeat(np.cumsum(counts) - counts, counts)
    return np.append(knots[segment] + lengths[segment] * offset / counts[segment], knots[-1])


def _check_gravity(problem: ToppraProblem) -> None:
    """Raise when holding still against gravity already breaks a torque limit on the path.

    Checked at the gridpoints and halfway between them.
    """
    robot = problem.robot
    assert robot is not None  # _assemble made sure
    grid = problem.grid
    s = np.sort(np.concatenate([grid, 0.5 * (grid[:-1] + grid[1:])]))
    tau = robot.gravity_torque(problem.path.native(s))
    _raise_gravity(problem, np.abs(tau), s, None)


def _raise_gravity(
    problem: ToppraProblem, gravity: FloatArray, s: FloatArray, t: FloatArray | None
) -> None:
    """Raise InfeasibleError if |gravity torque| (shape (m, n)) exceeds an effort limit."""
    limits = problem.limits
    excess = gravity / limits.effort
    k, j = np.unravel_index(int(np.argmax(excess)), excess.shape)
    if excess[k, j] <= 1.0:
        return
    name = limits.names[j]
    unit = problem.path.unit
    when = "" if t is None else f" (t = {t[k]:.6g} s of the retimed motion)"
    raise InfeasibleError(
        f"gravity alone needs {gravity[k, j]:.6g} {limits.unit('effort', j)} at joint "
        f"{name!r} at path position s = {s[k]:.6g} {unit}{when}, beyond its limit "
        f"{limits.effort[j]:.6g}: no timing of this path respects the torque limits",
        limit="torque",
        joint=name,
        required=float(gravity[k, j]),
        allowed=float(limits.effort[j]),
    )


def _end_bound(problem: ToppraProblem, scale: dict[str, float]) -> float:
    """Largest squared path velocity the (shrunk) limits allow at the path's end.

    At the end the path velocity must respect the speed caps, and some path acceleration
    must keep every joint acceleration (and torque) within its limit: a linear program in
    (u, x), solved with scipy's HiGHS. Returns -1 when nothing is feasible there.
    """
    from scipy.optimize import linprog

    path = problem.path
    limits = problem.limits
    last = path.coefficients[-1:]
    length = np.diff(path.knots)[-1:]
    first, second = (d[-1:] for d in path.derivatives)
    q = _polyval_local(last, length)[0]
    qs = _polyval_local(first, length)[0]
    qss = _polyval_local(second, length)[0]
    rates = [np.abs(qs) / (limits.velocity * scale["velocity"])]
    robot = problem.robot
    if problem.tool_speed is not None and robot is not None:
        speed = _tool_speed_factor(robot, q[None], qs[None])
        rates.append(speed / (problem.tool_speed * scale["tool speed"]))
    peak = float(np.max(np.concatenate(rates)))
    x_speed = math.inf if peak == 0.0 else 1.0 / peak**2
    rows = [(qs, qss, np.zeros_like(qs), limits.acceleration * scale["acceleration"])]
    if problem.torque and robot is not None:
        zero = np.zeros_like(q)
        gravity = robot.inverse_dynamics(q, zero, zero)
        a = robot.inverse_dynamics(q, zero, qs) - gravity
        b = robot.inverse_dynamics(q, qs, qss) - gravity
        rows.append((a, b, gravity, limits.effort * scale["torque"]))
    matrix = np.vstack([np.column_stack([s * a, s * b]) for a, b, _, _ in rows for s in (1, -1)])
    rhs = np.concatenate([lim - s * c for _, _, c, lim in rows for s in (1, -1)])
    upper = min(x_speed, _X_CAP)
    result = linprog([0.0, -1.0], A_ub=matrix, b_ub=rhs, bounds=[(None, None), (0.0, upper)])
    return float(result.x[1]) if result.status == 0 else -1.0


def _check_end_velocity(problem: ToppraProblem, scale: dict[str, float]) -> None:
    """Raise when the requested end path velocity is beyond the limits at the path's end.

    toppra 0.6.10 does not impose the velocity bounds (``xbound``) at the last gridpoint, so
    a too fast end would come back as a "successful" parametrisation.
    """
    x_max = _end_bound(problem, scale)
    if problem.sd_end**2 <= x_max * (1.0 + 1e-9):
        return
    limits = problem.limits
    unit = problem.path.unit
    allowed = math.sqrt(max(x_max, 0.0))
    qs = problem.path.native(problem.grid[-1:], 1)[0]
    need = problem.sd_end * np.abs(qs) / limits.velocity
    j = int(np.argmax(need))
    binding = need[j] > scale["velocity"]
    detail = (
        f": joint {limits.names[j]!r} would move at {problem.sd_end * abs(qs[j]):.6g} "
        f"{limits.unit('velocity', j)}, limit {limits.velocity[j]:.6g}"
        if binding
        else ""
    )
    raise InfeasibleError(
        f"end path velocity {problem.sd_end:.6g} {unit}/s is beyond what the limits allow at "
        f"the end of the path{detail}; the largest feasible end path velocity is "
        f"{allowed:.6g} {unit}/s (rate limits shrunk by {MARGIN:.1%} as a margin for the "
        "motion between gridpoints)",
        limit="path velocity",
        joint=limits.names[j] if binding else None,
        required=problem.sd_end,
        allowed=allowed,
    )


def _raise_failure(problem: ToppraProblem, instance: Any, sd: Any, K: Any) -> None:
    """Turn toppra's failed parametrisation into a typed error carrying the reason."""
    grid = problem.grid
    unit = problem.path.unit
    note = f" (rate limits shrunk by {MARGIN:.1%} as a margin for the motion between gridpoints)"
    if K is not None and np.isnan(K).any():
        k = int(np.max(np.flatnonzero(np.isnan(K).any(axis=1))))
        raise InfeasibleError(
            f"the controllable set is empty at grid index {k} of {grid.size - 1} (s = "
            f"{grid[k]:.6g} {unit}): from no path velocity there can the motion reach the end "
            f"at path velocity {problem.sd_end:.6g} {unit}/s within the "
            f"{'torque, ' if problem.torque else ''}velocity and acceleration limits{note}",
            limit="torque" if problem.torque else "path velocity",
            required=problem.sd_end,
        )
    if K is not None and sd is None:
        low, high = (math.sqrt(max(float(v), 0.0)) for v in K[0])
        if problem.sd_start > high:
            reason = f"the largest feasible start path velocity is {high:.6g} {unit}/s"
            allowed = high
        else:
            reason = (
                f"from it the end path velocity {problem.sd_end:.6g} {unit}/s cannot be "
                f"reached; the start path velocity must lie in [{low:.6g}, {high:.6g}] {unit}/s"
            )
            allowed = low
        raise InfeasibleError(
            f"start path velocity {problem.sd_start:.6g} {unit}/s is not feasible: {reason}{note}",
            limit="path velocity",
            required=problem.sd_start,
            allowed=allowed,
        )
    values = np.asarray(sd, dtype=float) if sd is not None else np.full(grid.size, np.nan)
    bad = np.flatnonzero(~np.isfinite(values))
    where = f" at grid index {int(bad[0])} (s = {grid[int(bad[0])]:.6g} {unit})" if bad.size else ""
    raise SolverError(
        "toppra",
        str(instance.problem_data.return_code.name),
        detail=f"the forward pass failed{where} although the path is controllable",
    )


class _Samples:
    """Limited quantities of a solved grid at fractions of some grid intervals' durations.

    Attributes:
        values: Signed value / limit of every limited quantity, shape (M, P, k) for M
            intervals and P fractions (tool speed: its magnitude over the cap).
        columns: The columns of each quantity (``"velocity"``, ``"acceleration"``,
            ``"tool speed"``, ``"torque"``) in ``values``.
        s: Path positions of the samples, shape (M * P,), when torques or the tool speed
            are limited (else empty).
        gravity: Gravity torques, shape (M * P, n), when torques are limited, else None.
        dynamic: Torques minus gravity torques, same shape, or None.
    """

    def __init__(
        self,
        problem: ToppraProblem,
        law: _TimeLaw,
        intervals: NDArray[np.intp],
        fractions: FloatArray,
    ) -> None:
        limits = problem.limits
        path = problem.path
        segment = problem.segment[intervals]
        tau = (law.t[intervals + 1] - law.t[intervals])[:, None] * fractions
        u = law.u[intervals, None]
        v0 = law.sd[intervals, None]
        sd = v0 + u * tau
        offset = law.grid[intervals] - path.knots[segment]
        sigma = offset[:, None] + (v0 + 0.5 * u * tau) * tau
        first, second = path.derivatives
        qs = _polyval_grid(first[segment], sigma)  # (M, P, n)
        qss = _polyval_grid(second[segment], sigma)
        qd = qs * sd[:, :, None]
        qdd = qs * u[:, :, None] + qss * (sd * sd)[:, :, None]
        n = limits.n
        parts = [qd * (1.0 / limits.velocity), qdd * (1.0 / limits.acceleration)]
        self.columns: dict[str, slice] = {"velocity": slice(0, n), "acceleration": slice(n, 2 * n)}
        self.s = np.empty(0)
        self.gravity: FloatArray | None = None
        self.dynamic: FloatArray | None = None
        robot = problem.robot
        if robot is not None and (problem.torque or problem.tool_speed is not None):
            self.s = (law.grid[intervals, None] + sigma - offset[:, None]).ravel()
            shape = (*sigma.shape, -1)
            q = _polyval_grid(path.coefficients[segment], sigma).reshape(-1, n)
            flat_qd = qd.reshape(-1, n)
            if problem.tool_speed is not None:
                speed = _tool_speed_factor(robot, q, flat_qd) / problem.tool_speed
                self.columns["tool speed"] = slice(2 * n, 2 * n + 1)
                parts.append(speed.reshape(shape))
            if problem.torque:
                self.gravity = robot.gravity_torque(q)
                _raise_gravity(problem, np.abs(self.gravity), self.s, law.time_at(self.s))
                torque = robot.inverse_dynamics(q, flat_qd, qdd.reshape(-1, n))
                self.dynamic = torque - self.gravity
                start = sum(part.shape[2] for part in parts)
                self.columns["torque"] = slice(start, start + n)
                parts.append((torque / limits.effort).reshape(shape))
        self.values = np.concatenate(parts, axis=2)


@cache
def _bernstein(points: int) -> FloatArray:
    """Map from samples to Bernstein coefficients, shape (points, points).

    Takes a polynomial's values at ``points`` evenly spaced instants of [0, 1] (both ends
    included) to its Bernstein coefficients of degree ``points - 1``.
    """
    degree = points - 1
    x = np.linspace(0.0, 1.0, points)[:, None]
    i = np.arange(points)[None, :]
    binomial = np.array([math.comb(degree, k) for k in range(points)])[None, :]
    return np.linalg.inv(binomial * x**i * (1.0 - x) ** (degree - i))


def _bounds(values: FloatArray) -> FloatArray:
    """Upper bounds of |p| over each interval, shape (M, k), from samples (M, P, k).

    The samples are at P evenly spaced instants of each interval, both ends included. A
    polynomial of degree < P lies within the hull of its Bernstein coefficients, so the
    largest coefficient magnitude bounds it; the bound exceeds the true maximum by a term
    of second order in the interval's length.
    """
    coefficients = np.einsum("ij,mjk->mik", _bernstein(values.shape[1]), values)
    return np.max(np.abs(coefficients), axis=1)


def _verify(
    problem: ToppraProblem, law: _TimeLaw
) -> tuple[dict[str, float], dict[str, float], float, NDArray[np.intp]]:
    """Bounds on the ratio of each limited quantity to its limit, and the slow-down.

    On a grid interval, joint velocity and acceleration are polynomials in time of degree
    below twice the path's (the path composed with the quadratic s(t)); they are sampled at
    that many evenly spaced instants and bounded by their Bernstein coefficients (exact
    bounds, a little above the true peaks). Intervals whose bound exceeds
    ``1 - MARGIN / 2`` are split into :data:`_SUBDIVIDE` parts and bounded again, which
    tightens the bound. Torques and the tool speed (not polynomials) are bounded the same
    way, as estimates.

    Returns:
        (ratios, ratios after the slow-down, c, over): each ratio bounds the worst
        |value| / limit of a quantity; c <= 1 is the factor on the path velocity (speeds
        scale by c, accelerations and the non-gravity part of torques by c^2) that brings
        every bound to at most ``1 - MARGIN / 2``, 1 when none exceeds it; ``over`` lists
        the grid intervals whose bound exceeds that.

    Raises:
        InfeasibleError: Gravity alone breaks a torque limit at a sampled instant, or
            takes so much of it that no slow-down helps.
    """
    points = max(2 * (problem.path.coefficients.shape[1] - 1), 5)
    fractions = np.linspace(0.0, 1.0, points)
    coarse = _Samples(problem, law, np.arange(law.grid.size - 1), fractions)
    bounds = _bounds(coarse.values)  # (N, k)
    sets = [coarse]
    again = np.flatnonzero(np.max(bounds, axis=1) > _TARGET)
    if again.size:
        parts = (np.arange(_SUBDIVIDE)[:, None] + fractions[None, :]) / _SUBDIVIDE
        fine = _Samples(problem, law, again, parts.ravel())
        sets.append(fine)
        shape = (again.size * _SUBDIVIDE, points, -1)
        finer = _bounds(fine.values.reshape(shape)).reshape(again.size, _SUBDIVIDE, -1)
        bounds[again] = np.max(finer, axis=1)
    ratios = {name: float(np.max(bounds[:, cols])) for name, cols in coarse.columns.items()}
    over = np.flatnonzero(np.max(bounds, axis=1) > _TARGET)
    # largest c^2 that keeps each quantity within TARGET
    squared = min(
        1.0,
        (_TARGET / max(ratios["velocity"], 1e-300)) ** 2,
        _TARGET / max(ratios["acceleration"], 1e-300),
    )
    if "tool speed" in ratios:
        squared = min(squared, (_TARGET / max(ratios["tool speed"], 1e-300)) ** 2)
    if "torque" in ratios:
        squared = min(squared, _torque_room(problem, sets, ratios["torque"]))
    after = {
        "velocity": ratios["velocity"] * math.sqrt(squared),
        "acceleration": ratios["acceleration"] * squared,
    }
    if "tool speed" in ratios:
        after["tool speed"] = ratios["tool speed"] * math.sqrt(squared)
    if "torque" in ratios:
        effort = problem.limits.effort
        after["torque"] = max(
            float(np.max(np.abs(part.gravity + squared * part.dynamic) / effort))
            for part in sets
            if part.gravity is not None and part.dynamic is not None
        )
    return ratios, after, math.sqrt(squared), over


def _torque_room(problem: ToppraProblem, sets: list[_Samples], worst: float) -> float:
    r"""Largest c^2 that keeps every sampled torque within TARGET after the slow-down.

    A slow-down by c scales the non-gravity part of each torque by c^2:
    :math:`|g + c^2 d| \le` allowed, per sample and joint, with allowed the larger of
    TARGET x effort and |g| (gravity itself is held, checked before).

    Raises:
        InfeasibleError: Gravity leaves no room at some sample (no slow-down helps).
    """
    limits = problem.limits
    effort = limits.effort
    room = 1.0
    for part in sets:
        if part.gravity is None or part.dynamic is None:
            continue
        gravity, dynamic = part.gravity, part.dynamic
        torque = gravity + dynamic
        allowed = np.maximum(_TARGET * effort, np.abs(gravity))
        over = np.abs(torque) > allowed
        if not np.any(over):
            continue
        d = dynamic[over]
        each = (np.sign(d) * allowed[over] - gravity[over]) / d
        room = min(room, float(np.min(each)))
        if room <= 1e-12:
            k, j = (int(v[0]) for v in np.nonzero(over))
            raise InfeasibleError(
                f"gravity takes {abs(gravity[k, j]):.6g} of the {effort[j]:.6g} "
                f"{limits.unit('effort', j)} torque limit of joint {limits.names[j]!r} at "
                f"s = {part.s[k]:.6g} {problem.path.unit}: the path cannot be followed at any "
                f"speed within the torque limits (the worst torque is {worst:.4g} x its limit)",
                limit="torque",
                joint=limits.names[j],
                required=float(abs(torque[k, j])),
                allowed=float(effort[j]),
            )
    return room
