"""Typed errors for what TOPPRA cannot do on a path, found before and after the solve.

Before the solve: a torque limit that gravity alone breaks on the path
(:func:`check_gravity`), an end path velocity beyond what the limits allow at the path's end
(:func:`check_end_velocity`; toppra itself does not bound it). After a failed solve,
:func:`raise_failure` names the reason: an empty controllable set (its grid index and path
position) or an infeasible start path velocity (the requested and the largest feasible
value) is an :class:`~optraj.errors.InfeasibleError`, a failed forward pass a
:class:`~optraj.errors.SolverError`. Never ``None``.
"""

from __future__ import annotations

import math
from typing import Any, NoReturn

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, SolverError
from optraj.planners.time_optimal.toppra_constraints import X_CAP, tool_speed_factor
from optraj.planners.time_optimal.toppra_path import polyval_local
from optraj.planners.time_optimal.toppra_problem import MARGIN, ToppraProblem

__all__ = ["check_end_velocity", "check_gravity", "raise_failure", "raise_gravity"]

FloatArray = NDArray[np.float64]


def check_gravity(problem: ToppraProblem) -> None:
    """Raise when holding still against gravity already breaks a torque limit on the path.

    Checked at the gridpoints and halfway between them.
    """
    robot = problem.robot
    assert robot is not None  # Toppra.build requires the robot for torque limits
    grid = problem.grid
    s = np.sort(np.concatenate([grid, 0.5 * (grid[:-1] + grid[1:])]))
    tau = robot.gravity_torque(problem.path.native(s))
    raise_gravity(problem, np.abs(tau), s, None)


def raise_gravity(
    problem: ToppraProblem, gravity: FloatArray, s: FloatArray, t: FloatArray | None
) -> None:
    """Raise InfeasibleError if |gravity torque| (shape (m, n)) exceeds an effort limit."""
    limits = problem.limits
    excess = gravity / limits.effort
    k, j = (int(v) for v in np.unravel_index(int(np.argmax(excess)), excess.shape))
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
    q = polyval_local(last, length)[0]
    qs = polyval_local(first, length)[0]
    qss = polyval_local(second, length)[0]
    rates = [np.abs(qs) / (limits.velocity * scale["velocity"])]
    robot = problem.robot
    if problem.tool_speed is not None and robot is not None:
        speed = tool_speed_factor(robot, q[None], qs[None])
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
    upper = min(x_speed, X_CAP)
    result = linprog([0.0, -1.0], A_ub=matrix, b_ub=rhs, bounds=[(None, None), (0.0, upper)])
    return float(result.x[1]) if result.status == 0 else -1.0


def check_end_velocity(problem: ToppraProblem, scale: dict[str, float]) -> None:
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


def raise_failure(problem: ToppraProblem, instance: Any, sd: Any, K: Any) -> NoReturn:
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
