r"""TOPPRA's answer as exact trajectories: the constant-acceleration time law and q(t).

With toppra's ``ParametrizeConstAccel`` the path acceleration is constant on each grid
interval, so :math:`s(t)` is quadratic there (:class:`TimeLaw`); the path is a piecewise
cubic (or any piecewise polynomial) in :math:`s`, and every knot is a gridpoint, so on each
grid interval :math:`q(t)` is one polynomial of twice the path's degree (6 for a cubic).
:func:`compose` builds these exactly: the trajectory *is* toppra's answer, sampled nowhere.

Example::

    breakpoints, coefficients = compose(path.knots, path.coefficients, grid, sd)
    traj = Trajectory(breakpoints, coefficients)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.planners.time_optimal.toppra_path import segment_of

__all__ = ["TimeLaw", "compose", "compose_law"]

FloatArray = NDArray[np.float64]


class TimeLaw:
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
    law = TimeLaw(np.asarray(grid, dtype=float), np.asarray(sd, dtype=float))
    return compose_law(np.asarray(knots, dtype=float), np.asarray(coefficients, dtype=float), law)


def compose_law(
    knots: FloatArray,
    coefficients: FloatArray,
    law: TimeLaw,
    segment: NDArray[np.intp] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """:func:`compose` under a built time law; faster when every knot is a gridpoint.

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
        segment = segment_of(knots, s_a)
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
