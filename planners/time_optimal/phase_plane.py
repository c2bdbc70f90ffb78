r"""TOPPRA's phase plane: the planned path velocity against the largest one the limits allow.

TOPPRA retimes a geometric path :math:`q(s)` by choosing the path velocity :math:`\dot s` at
each gridpoint. Every constraint is linear in the path acceleration :math:`u = \ddot s` and
the squared path velocity :math:`x = \dot s^2`,

.. math:: a(s)\,u + b(s)\,x + c(s) \in \mathcal{C}(s),

(joint velocities: :math:`|q'(s)|\,\dot s \le v`; joint accelerations:
:math:`|q'(s)\,u + q''(s)\,x| \le a`; torques through inverse dynamics). In the phase plane
:math:`(s, \dot s)` a :class:`PhasePlane` holds, at each gridpoint:

* the maximum velocity curve, ``sd_max``: the largest :math:`\dot s` for which some
  :math:`u` meets every constraint there (toppra's feasible set, under the limits
  themselves);
* each limit's own bound, ``bounds``: the same for that quantity alone (``inf`` where it
  bounds nothing, as the accelerations of a straight line, or nothing below toppra's cap);
  where one is the lowest, that limit binds;
* the controllable bound, ``sd_controllable``: the largest :math:`\dot s` from which the end
  of the path can still be reached (toppra's backward pass);
* the plan, ``sd``: the forward pass, greedy under the controllable bound.

The plan is solved under limits shrunk by
:data:`~planners.time_optimal.toppra_problem.MARGIN` (further where a re-solve needed it),
so it stays just under ``sd_max``; the controllable bound is the one of that solve.
:func:`~planners.time_optimal.phase_plane_plot.plot_phase_plane` draws a phase plane.

Example::

    toppra = planners.Toppra()
    problem = toppra.build(waypoints, robot.limits)    # the problem, open to inspection
    traj = toppra.solve(problem)
    plane = phase_plane(problem, traj)
    plane.sd / plane.sd_max                            # how near the plan runs to the limits
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.time_optimal.toppra_grid import stretch_factor
from optraj.planners.time_optimal.toppra_path import toppra_classes
from optraj.planners.time_optimal.toppra_problem import ToppraProblem, initial_scale
from optraj.planners.trajectory import Trajectory

__all__ = ["PhasePlane", "phase_plane"]

FloatArray = NDArray[np.float64]

#: Relative distance from toppra's cap on a feasible set (``toppra.constants.CVXPY_MAXX``)
#: within which a squared path velocity counts as unbounded.
_CAP_SHARE = 1.0 - 1e-6
#: What the planner stamps on a TOPPRA trajectory, and this module reads back.
_KEYS = ("grid", "path_velocity", "controllable_sets")


@dataclass(frozen=True, eq=False)
class PhasePlane:
    """A TOPPRA plan in the phase plane (s, s-dot), with the bounds the limits set.

    Path units: joint-space chord length [rad or m] for a waypoint path or a straight line,
    time [s] for a trajectory used as a path (``unit``).

    Attributes:
        s: Gridpoints [path units], shape (N + 1,).
        sd: Planned path velocity at the gridpoints [path units/s], shape (N + 1,).
        sd_max: Maximum velocity curve: the largest path velocity every constraint allows
            at each gridpoint [path units/s], shape (N + 1,).
        sd_controllable: The largest path velocity at each gridpoint from which the end can
            still be reached [path units/s], shape (N + 1,).
        bounds: Each limited quantity alone (``"velocity"``, ``"acceleration"``, and
            ``"torque"``, ``"tool speed"`` when the problem limits them): the largest path
            velocity it allows [path units/s], shape (N + 1,).
        unit: The path unit: ``"rad"`` (chord length; also for prismatic joints, in m) or
            ``"s"``.

    ``sd_max`` and a bound are ``inf`` where the constraints set no bound below toppra's cap
    on a feasible set (``toppra.constants.CVXPY_MAXX`` = 1e4 on s-dot squared: 100 path
    units/s, more on a short path, which is solved stretched): where they set none at all
    (accelerations on a straight line, a path at rest) or only one far above any plan.
    """

    s: FloatArray
    sd: FloatArray
    sd_max: FloatArray
    sd_controllable: FloatArray
    bounds: Mapping[str, FloatArray]
    unit: str

    @property
    def binding(self) -> tuple[str, ...]:
        """The quantity whose bound is the lowest at each gridpoint, shape (N + 1,)."""
        names = tuple(self.bounds)
        stacked = np.stack([self.bounds[name] for name in names])
        return tuple(names[k] for k in np.argmin(stacked, axis=0))


def phase_plane(problem: ToppraProblem, trajectory: Trajectory) -> PhasePlane:
    """The phase plane of a TOPPRA plan: its path velocity and the bounds on it.

    Args:
        problem: The built problem, from :meth:`Toppra.build
            <planners.time_optimal.toppra_planner.Toppra.build>`.
        trajectory: Its solution, from :meth:`Toppra.solve
            <planners.time_optimal.toppra_planner.Toppra.solve>` (the grid it was solved on
            is read from its metadata; a refined grid holds more gridpoints).

    Returns:
        The phase plane on the trajectory's grid.

    Raises:
        InvalidInputError: ``problem`` is not a ToppraProblem, ``trajectory`` is not a
            Trajectory retimed by TOPPRA, or it was retimed along another path.
        SolverError: toppra finds no feasible path velocity at a gridpoint (the path cannot
            be followed there at all; a solved problem never has one).
    """
    if not isinstance(problem, ToppraProblem):
        raise InvalidInputError(
            f"problem must be a ToppraProblem (from Toppra.build), got {type(problem).__name__}",
            name="problem",
        )
    grid, sd, controllable = _plan_of(problem, trajectory)
    names = tuple(initial_scale(problem))
    constraints = problem.constraints(dict.fromkeys(names, 1.0))  # the limits themselves
    bounds = {
        name: _largest_sd(problem, [constraint], grid, name)
        for name, constraint in zip(names, constraints, strict=True)
    }
    return PhasePlane(
        s=grid,
        sd=sd,
        sd_max=_largest_sd(problem, constraints, grid, "every limit"),
        sd_controllable=np.sqrt(np.maximum(controllable, 0.0)),
        bounds=bounds,
        unit=problem.path.unit,
    )


def _plan_of(
    problem: ToppraProblem, trajectory: Trajectory
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(grid, planned path velocity, highest controllable x) stamped on a TOPPRA trajectory."""
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    missing = [key for key in _KEYS if key not in trajectory.metadata]
    if missing:
        planner = trajectory.metadata.get("planner", "no planner")
        raise InvalidInputError(
            f"the trajectory (planned by {planner!r}) was not retimed by planners.Toppra: its "
            f"metadata has no {', '.join(repr(key) for key in missing)}",
            name="trajectory",
        )
    grid = np.asarray(trajectory.metadata["grid"], dtype=float).reshape(-1)
    sd = np.asarray(trajectory.metadata["path_velocity"], dtype=float).reshape(-1)
    sets = np.asarray(trajectory.metadata["controllable_sets"], dtype=float).reshape(-1, 2)
    ends = problem.path.knots[[0, -1]]
    span = float(ends[1] - ends[0])
    if (
        grid.size < 2
        or sd.size != grid.size
        or sets.shape[0] != grid.size
        or not np.allclose(grid[[0, -1]], ends, rtol=0.0, atol=1e-9 * span)
    ):
        raise InvalidInputError(
            f"the trajectory was retimed along another path: its grid spans "
            f"[{grid[0]:.6g}, {grid[-1]:.6g}] with {grid.size} gridpoints, {sd.size} path "
            f"velocities; the problem's path spans [{ends[0]:.6g}, {ends[1]:.6g}] "
            f"{problem.path.unit}",
            name="trajectory",
        )
    return grid, sd, sets[:, 1]


def _largest_sd(
    problem: ToppraProblem, constraints: list[Any], grid: FloatArray, what: str
) -> FloatArray:
    """The largest path velocity ``constraints`` allow at each gridpoint [path units/s].

    toppra's feasible sets, computed in the stretched parameter the planner solves in (see
    :func:`~planners.time_optimal.toppra_grid.stretch_factor`); ``inf`` where toppra's cap
    is reached (the constraints set no bound there).
    """
    stretch = stretch_factor(problem.path)
    path = problem.path if stretch == 1.0 else problem.path.stretched(stretch)
    algorithm = toppra_classes().TOPPRA(constraints, path.native, grid * stretch)
    highest = np.asarray(algorithm.compute_feasible_sets(), dtype=float)[:, 1]
    empty = np.flatnonzero(~(highest >= 0.0))
    if empty.size:
        k = int(empty[0])
        raise SolverError(
            "toppra",
            "empty feasible set",
            detail=(
                f"no path velocity meets {what} at gridpoint {k} (s = {grid[k]:.6g} "
                f"{problem.path.unit}): the path cannot be followed there"
            ),
        )
    cap = float(importlib.import_module("toppra.constants").CVXPY_MAXX)
    sd = np.sqrt(highest) / stretch
    return np.where(highest >= _CAP_SHARE * cap, np.inf, sd)
