"""A geometric path through waypoints, and its checks before TOPPRA retimes it.

A path must stay within the joint position limits (TOPPRA only chooses the timing) and must
have no corner (a tangent that jumps at a knot can only be passed at rest). The path through
waypoints, :func:`waypoint_path`, is built to pass them: the spline where it stays within
the limits, else the shape-preserving PCHIP cubic, confirmed here.

Example::

    path, knot_of_waypoint = waypoint_path(waypoints, robot.limits)
    check_tangent(path, robot.limits)          # raises InvalidInputError at a corner
    check_path_positions(path, robot.limits)   # raises JointLimitError naming the joint
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, JointLimitError
from optraj.planners.time_optimal.toppra_path import GeometricPath, derivative, polyval_local
from optraj.problems.point_to_point import STILL_TOLERANCE
from optraj.robots import JointLimits

__all__ = ["check_path_positions", "check_tangent", "waypoint_path"]

FloatArray = NDArray[np.float64]


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
    slope = derivative(coefficients)
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


def check_path_positions(path: GeometricPath, limits: JointLimits) -> None:
    """Raise for the joint whose path goes furthest beyond its position limits.

    Raises:
        JointLimitError: Naming the joint, the value and the path position.
    """
    error = _position_excess(path, limits)
    if error is not None:
        raise error


def check_tangent(path: GeometricPath, limits: JointLimits) -> None:
    """Raise when the path's tangent jumps at a knot (a corner: passable only at rest)."""
    coeffs = path.coefficients
    if coeffs.shape[0] < 2:
        return
    first = derivative(coeffs)
    left = polyval_local(first[:-1], np.diff(path.knots)[:-1])
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


def waypoint_path(
    points: FloatArray, limits: JointLimits
) -> tuple[GeometricPath, NDArray[np.intp]]:
    """The spline through waypoints, or the PCHIP cubic where the spline leaves the limits.

    The PCHIP cubic is shape-preserving: it stays within the range of the waypoints, so
    within the position limits when they are.

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
        check_path_positions(path, limits)  # holds by construction; cheap to confirm
    return path, np.cumsum(new) - 1


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
