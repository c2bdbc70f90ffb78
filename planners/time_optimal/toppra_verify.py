"""Bounds on every limited quantity of a solved grid between its gridpoints.

toppra imposes its constraints only at the gridpoints (here at both ends of each grid
interval, toppra's "interpolation" discretisation), so in between a limit can be exceeded
slightly. :func:`verify` bounds each quantity over every grid interval: joint velocity and
acceleration are polynomials in time there, bounded exactly (from above) by their Bernstein
coefficients, computed from as many samples as their degree needs (6 for a cubic path;
torques and the tool speed are bounded the same way, as estimates). It also gives the
uniform slow-down that would bring every bound to :data:`TARGET` of its limit, and the grid
intervals still above it, for :func:`~planners.time_optimal.toppra_solve.solve` to act on.

Example::

    check = verify(problem, TimeLaw(problem.grid, sd))
    check.ratios["velocity"]       # bound on max |qd_j| / limit_j over the whole motion
    check.slowdown                 # factor c <= 1 on the path velocity that would fix it
"""

from __future__ import annotations

import math
from functools import cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError
from optraj.planners.time_optimal.toppra_constraints import tool_speed_factor
from optraj.planners.time_optimal.toppra_failures import raise_gravity
from optraj.planners.time_optimal.toppra_path import polyval_grid
from optraj.planners.time_optimal.toppra_problem import MARGIN, ToppraProblem
from optraj.planners.time_optimal.toppra_time_law import TimeLaw

__all__ = ["TARGET", "Verification", "verify"]

FloatArray = NDArray[np.float64]

#: Verified ratios up to this pass; above it a motion is slowed down or solved again.
TARGET = 1.0 - 0.5 * MARGIN
#: Parts into which a grid interval whose bound exceeds the target is split and bounded again.
_SUBDIVIDE = 8


class Verification(NamedTuple):
    """What :func:`verify` found on a solved grid.

    Attributes:
        ratios: Per limited quantity (``"velocity"``, ``"acceleration"``, ``"tool speed"``,
            ``"torque"``), a bound on its worst |value| / limit.
        after: The same bounds after the slow-down by ``slowdown``.
        slowdown: Factor c <= 1 on the path velocity (speeds scale by c, accelerations and
            the non-gravity part of torques by c^2) that brings every bound to at most
            :data:`TARGET`; 1 when none exceeds it.
        over: The grid intervals whose bound exceeds :data:`TARGET`, shape (k,).
    """

    ratios: dict[str, float]
    after: dict[str, float]
    slowdown: float
    over: NDArray[np.intp]


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
        law: TimeLaw,
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
        qs = polyval_grid(first[segment], sigma)  # (M, P, n)
        qss = polyval_grid(second[segment], sigma)
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
            q = polyval_grid(path.coefficients[segment], sigma).reshape(-1, n)
            flat_qd = qd.reshape(-1, n)
            if problem.tool_speed is not None:
                speed = tool_speed_factor(robot, q, flat_qd) / problem.tool_speed
                self.columns["tool speed"] = slice(2 * n, 2 * n + 1)
                parts.append(speed.reshape(shape))
            if problem.torque:
                self.gravity = robot.gravity_torque(q)
                raise_gravity(problem, np.abs(self.gravity), self.s, law.time_at(self.s))
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
    return np.asarray(np.linalg.inv(binomial * x**i * (1.0 - x) ** (degree - i)), dtype=np.float64)


def _bounds(values: FloatArray) -> FloatArray:
    """Upper bounds of |p| over each interval, shape (M, k), from samples (M, P, k).

    The samples are at P evenly spaced instants of each interval, both ends included. A
    polynomial of degree < P lies within the hull of its Bernstein coefficients, so the
    largest coefficient magnitude bounds it; the bound exceeds the true maximum by a term
    of second order in the interval's length.
    """
    coefficients = np.einsum("ij,mjk->mik", _bernstein(values.shape[1]), values)
    return np.max(np.abs(coefficients), axis=1)


def verify(problem: ToppraProblem, law: TimeLaw) -> Verification:
    """Bounds on the ratio of each limited quantity to its limit, and the slow-down.

    On a grid interval, joint velocity and acceleration are polynomials in time of degree
    below twice the path's (the path composed with the quadratic s(t)); they are sampled at
    that many evenly spaced instants and bounded by their Bernstein coefficients (exact
    bounds, a little above the true peaks). Intervals whose bound exceeds
    ``1 - MARGIN / 2`` are split into :data:`_SUBDIVIDE` parts and bounded again, which
    tightens the bound. Torques and the tool speed (not polynomials) are bounded the same
    way, as estimates.

    Returns:
        The bounds, those after the slow-down, the slow-down factor and the grid intervals
        still above :data:`TARGET` (``1 - MARGIN / 2``); see :class:`Verification`.

    Raises:
        InfeasibleError: Gravity alone breaks a torque limit at a sampled instant, or
            takes so much of it that no slow-down helps.
    """
    points = max(2 * (problem.path.coefficients.shape[1] - 1), 5)
    fractions = np.linspace(0.0, 1.0, points)
    coarse = _Samples(problem, law, np.arange(law.grid.size - 1), fractions)
    bounds = _bounds(coarse.values)  # (N, k)
    sets = [coarse]
    again = np.flatnonzero(np.max(bounds, axis=1) > TARGET)
    if again.size:
        parts = (np.arange(_SUBDIVIDE)[:, None] + fractions[None, :]) / _SUBDIVIDE
        fine = _Samples(problem, law, again, parts.ravel())
        sets.append(fine)
        shape = (again.size * _SUBDIVIDE, points, -1)
        finer = _bounds(fine.values.reshape(shape)).reshape(again.size, _SUBDIVIDE, -1)
        bounds[again] = np.max(finer, axis=1)
    ratios = {name: float(np.max(bounds[:, cols])) for name, cols in coarse.columns.items()}
    over = np.flatnonzero(np.max(bounds, axis=1) > TARGET)
    # largest c^2 that keeps each quantity within TARGET
    squared = min(
        1.0,
        (TARGET / max(ratios["velocity"], 1e-300)) ** 2,
        TARGET / max(ratios["acceleration"], 1e-300),
    )
    if "tool speed" in ratios:
        squared = min(squared, (TARGET / max(ratios["tool speed"], 1e-300)) ** 2)
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
    return Verification(ratios, after, math.sqrt(squared), over)


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
        allowed = np.maximum(TARGET * effort, np.abs(gravity))
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
