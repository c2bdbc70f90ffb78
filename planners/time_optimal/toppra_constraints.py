r"""The constraints TOPPRA retimes a path under, in toppra's canonical linear form.

Joint velocity and acceleration limits; optionally joint torques (toppra's
``JointTorqueConstraint`` fed by the robot's RNEA, no friction) and a cap on the tool frame
origin's speed, :math:`\lVert J_v(q)\,q'(s)\rVert\,\dot s \le v_{max}`. All are toppra
canonical linear constraints in the path acceleration :math:`u = \ddot s` and the squared
path velocity :math:`x = \dot s^2`. Speed caps (joint velocities, tool speed) are upper
bounds on :math:`x` at each gridpoint, so they only fill the ``xbound`` column, as toppra's
``JointVelocityConstraint`` does, and cost the stage-wise programs nothing; unlike it, the
bounds are chosen to hold between gridpoints too (:func:`chord_safe_bound`; toppra's own
hold only at the gridpoints, and joint speeds overshoot between them). Accelerations and
torques are discretised like toppra's "interpolation" scheme (both ends of each grid
interval), with two fixes: at a knot where the path's curvature jumps the interval ending
there uses the curvature before the knot (:func:`jump_rows`), and every row is normalised
(:func:`normalised_rows`), because toppra's Seidel solver uses absolute tolerances and
otherwise reports an empty controllable set on feasible paths where a joint barely moves.

The constraint classes themselves derive from toppra's and live in
:mod:`planners.time_optimal.toppra_classes`; :meth:`ToppraProblem.constraints
<planners.time_optimal.toppra_problem.ToppraProblem.constraints>` builds them from the
functions here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.planners.time_optimal.toppra_path import toppra_classes
from optraj.robots import Robot

__all__ = [
    "X_CAP",
    "ToppraPath",
    "chord_safe_bound",
    "joint_speed_rates",
    "jump_rows",
    "normalised_rows",
    "tool_speed_factor",
    "tool_speed_rates",
    "torque_constraint",
]

FloatArray = NDArray[np.float64]

#: Largest squared path velocity offered to toppra where nothing bounds it.
X_CAP = 1e16
#: Fractions of each grid interval at which speed caps are also evaluated.
_INTERIOR = np.array([0.25, 0.5, 0.75])


class ToppraPath(Protocol):
    """A path as toppra evaluates it: q(s) and its derivatives, called like a function.

    :attr:`GeometricPath.native <planners.time_optimal.toppra_path.GeometricPath.native>`
    is one. The functions here also read two optional attributes when present:
    ``rest_points`` (inner knots where the path is at rest) and ``curvature_jumps`` (knots
    where q'' jumps, see :func:`~planners.time_optimal.toppra_path.curvature_jumps`).
    """

    def __call__(self, path_positions: ArrayLike, order: int = 0, /) -> FloatArray:
        """The ``order``-th derivative of q at the path positions, shape (m, n)."""
        ...


def chord_safe_bound(
    rates: Callable[[ToppraPath, FloatArray], FloatArray], path: ToppraPath, grid: FloatArray
) -> FloatArray:
    r"""Upper bounds on :math:`x = \dot s^2` at the gridpoints that also hold in between.

    Let :math:`B(s) = 1 / \max_k r_k(s)^2` be the largest allowed :math:`x`. toppra keeps
    :math:`x_i \le B(s_i)`, but the output's :math:`x(s)` is linear on each grid interval and
    can rise above :math:`B` where :math:`B` sags between gridpoints. On each interval,
    sampled at fractions :math:`\theta` of its length (0.25, 0.5, 0.75):

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
        bound = np.minimum(1.0 / (peak * peak), X_CAP)
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


def joint_speed_rates(velocity: FloatArray) -> Callable[[ToppraPath, FloatArray], FloatArray]:
    """Joint speeds per unit path velocity over their limits, :math:`|q'(s)| / v`."""
    inverse = 1.0 / velocity

    def rates(path: ToppraPath, s: FloatArray) -> FloatArray:
        return np.abs(path(s, 1)) * inverse

    return rates


def tool_speed_rates(robot: Robot, cap: float) -> Callable[[ToppraPath, FloatArray], FloatArray]:
    """Tool origin speed per unit path velocity over the cap, :math:`|J_v q'(s)| / v_{max}`."""

    def rates(path: ToppraPath, s: FloatArray) -> FloatArray:
        return (tool_speed_factor(robot, path(s), path(s, 1)) / cap)[:, None]

    return rates


def tool_speed_factor(robot: Robot, q: FloatArray, qd: FloatArray) -> FloatArray:
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


def jump_rows(
    path: ToppraPath, gridpoints: FloatArray
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


def torque_constraint(robot: Robot, effort: FloatArray) -> Any:
    """The joint torque constraint of toppra, fed by the robot's RNEA, without friction."""
    lib = toppra_classes()
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
