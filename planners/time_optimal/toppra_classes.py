"""Classes derived from toppra's, for :class:`optraj.planners.Toppra`.

Imported on the first TOPPRA plan, not with :mod:`optraj.planners` (importing toppra imports
matplotlib.pyplot and scipy): the Seidel solver set up without toppra's solver probe, a
piecewise polynomial path, speed caps that hold between gridpoints, acceleration and torque
rows with left limits at curvature jumps, and toppra's constant-acceleration output with its
times from NumPy. They are plain module classes, so trajectories that hold them pickle.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint
import toppra.exceptions
import toppra.interpolator
import toppra.parametrizer
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PPoly

from optraj.planners.time_optimal.toppra_constraints import (
    ToppraPath,
    chord_safe_bound,
    jump_rows,
    normalised_rows,
)
from optraj.planners.time_optimal.toppra_passes import (
    controllable_sets,
    forward_pass,
    start_controllable,
)
from optraj.planners.time_optimal.toppra_path import GeometricPath, curvature_jumps

try:  # toppra 0.6's layout; any other: the public constructor below
    from toppra.algorithm.algorithm import ParameterizationAlgorithm
    from toppra.solverwrapper import cy_seidel_solverwrapper as seidel
except ImportError:  # pragma: no cover - depends on the installed toppra
    seidel = None

__all__ = [
    "TOPPRA",
    "AccelerationConstraint",
    "Collocation",
    "ConstAccelOutput",
    "Ok",
    "PolynomialPath",
    "SeidelTOPPRA",
    "SpeedConstraint",
    "TorqueConstraint",
]

FloatArray = NDArray[np.float64]

#: toppra's return code of a parametrisation that succeeded.
Ok = toppra.algorithm.ParameterizationReturnCode.Ok
#: toppra's collocation discretisation (the torque constraint is built with it).
Collocation = toppra.constraint.DiscretizationType.Collocation


class SeidelTOPPRA(toppra.algorithm.TOPPRA):
    """toppra's TOPPRA with its Seidel solver wrapper, built without the solver probe.

    ``ReachabilityAlgorithm.__init__`` looks for the optional solver packages (qpOASES,
    cvxpy, by importlib) on every construction, even when the wrapper is named. This
    builds the same instance as
    ``TOPPRA(constraints, path, gridpoints, solver_wrapper="seidel", parametrizer=...)``
    (the base initialisation, then the wrapper with the same arguments) without it.
    """

    def __init__(self, constraints: list[Any], path: Any, gridpoints: FloatArray) -> None:
        if seidel is None:  # pragma: no cover - depends on the installed toppra
            super().__init__(
                constraints,
                path,
                gridpoints=gridpoints,
                solver_wrapper="seidel",
                parametrizer="ParametrizeConstAccel",
            )
            return
        ParameterizationAlgorithm.__init__(
            self, constraints, path, gridpoints=gridpoints, parametrizer="ParametrizeConstAccel"
        )
        self.solver_wrapper = seidel.seidelWrapper(
            self.constraints, self.path, self.gridpoints, solve_lp1d=True
        )

    def compute_parameterization(
        self, sd_start: float, sd_end: float, return_data: bool = False
    ) -> tuple[Any, ...]:
        """The parametrisation of toppra's own, its two passes run by :mod:`.toppra_passes`.

        The same results, return codes and ``problem_data`` (``K``, ``sd_vec``,
        ``sdd_vec``, ``return_code``) as toppra's, with less work around each stage's solve.

        Returns:
            (sdd, sd, v) and, with ``return_data``, the controllable sets K; (None, None,
            None[, K]) when the problem is not controllable.
        """
        if seidel is None:  # pragma: no cover - depends on the installed toppra
            return tuple(super().compute_parameterization(sd_start, sd_end, return_data))
        if sd_end < 0 or sd_start < 0:
            raise toppra.exceptions.BadInputVelocities(
                f"Negative path velocities: path velocities must be positive: "
                f"({sd_start}, {sd_end})"
            )
        data = self._problem_data
        codes = toppra.algorithm.ParameterizationReturnCode
        solver = self.solver_wrapper
        sets = controllable_sets(solver, self._N, sd_end)
        controllable = not np.isnan(sets).any()
        if controllable:
            data.K = sets
            controllable = start_controllable(sets, sd_start)
        if not controllable:
            data.return_code = codes.FailUncontrollable
            return (None, None, None, sets) if return_data else (None, None, None)
        us, xs, extra = forward_pass(solver, sets, sd_start)
        sd, sdd = np.sqrt(xs), np.copy(us)
        data.sd_vec = sd
        data.sdd_vec = sdd
        data.return_code = codes.ErrUnknown if np.isnan(sd).any() else codes.Ok
        return (sdd, sd, extra, sets) if return_data else (sdd, sd, extra)


class PolynomialPath(toppra.interpolator.AbstractGeometricPath):
    """A piecewise polynomial path q(s) for toppra, evaluated by scipy's PPoly.

    Attributes:
        curvature_jumps: Knots where q'' jumps, with q, q' and the left q'' there (see
            :func:`curvature_jumps`); the acceleration and torque constraints read it.
        rest_points: Inner knots where the path is at rest (see
            :attr:`GeometricPath.rest_points`); the speed constraint reads it.
    """

    def __init__(self, path: GeometricPath) -> None:
        super().__init__()
        # PPoly wants descending powers, shape (d + 1, segments, n)
        self._pp = tuple(
            PPoly.construct_fast(np.ascontiguousarray(c[:, ::-1, :].transpose(1, 0, 2)), path.knots)
            for c in (path.coefficients, *path.derivatives)
        )
        self._interval = np.array([path.knots[0], path.knots[-1]])
        self._dof = path.dof
        self.curvature_jumps = curvature_jumps(path.knots, path.coefficients)
        self.rest_points = path.rest_points

    def __call__(self, path_positions: ArrayLike, order: int = 0) -> FloatArray:
        """The ``order``-th derivative of q at the path positions, shape (m, n)."""
        return self._pp[order](path_positions)

    @property
    def dof(self) -> int:
        """Number of joints."""
        return self._dof

    @property
    def path_interval(self) -> FloatArray:
        """First and last path position [rad or m along the path]."""
        return self._interval


class SpeedConstraint(toppra.constraint.LinearConstraint):
    r"""Speed caps that hold between gridpoints too: :math:`\max_k r_k(s)\,\dot s \le 1`.

    ``rates(path, s)`` gives each capped speed per unit path velocity over its cap,
    shape (m, k) (joint velocities: :math:`|q_j'(s)| / v_j`). Only ``xbound`` is set,
    by :func:`chord_safe_bound`.
    """

    def __init__(self, rates: Callable[[ToppraPath, FloatArray], FloatArray], dof: int) -> None:
        super().__init__()
        self.rates = rates
        self.dof = dof
        self._format_string = "    Speed caps, chord-safe\n"

    def compute_constraint_params(self, path: Any, gridpoints: FloatArray) -> tuple:
        """Toppra's constraint parameters: only ``xbound``, chord-safe at every gridpoint."""
        xbound = np.zeros((len(gridpoints), 2))
        xbound[:, 1] = chord_safe_bound(self.rates, path, np.asarray(gridpoints))
        return None, None, None, None, None, None, xbound


class AccelerationConstraint(toppra.constraint.LinearConstraint):
    r"""Joint acceleration limits, :math:`|q'(s)\,u + q''(s)\,x| \le a`.

    Discretised like toppra's ``JointAccelerationConstraint`` with its "interpolation"
    scheme (the limits hold at both ends of each grid interval, with the interval's u),
    but with two differences: at a knot where q'' jumps the end of the interval before
    it uses that segment's q'' (the left limit; toppra would take the next segment's),
    and every row is normalised (see :func:`normalised_rows`).
    """

    def __init__(self, limit: FloatArray) -> None:
        super().__init__()
        self.limit = np.asarray(limit, dtype=float)
        self.dof = self.limit.size
        self.identical = True
        self.discretization_type = toppra.constraint.DiscretizationType.Interpolation
        self._format_string = "    Joint accelerations, normalised rows\n"

    def compute_constraint_params(self, path: Any, gridpoints: FloatArray) -> tuple:
        """Toppra's constraint parameters: normalised rows at both ends of each interval."""
        grid = np.asarray(gridpoints, dtype=float)
        qs = path(grid, 1)
        qss = path(grid, 2)
        qss_end = qss[1:].copy()
        for row, _, _, _, left in jump_rows(path, grid):
            qss_end[row] = left
        a_end = qs[1:] + 2.0 * np.diff(grid)[:, None] * qss_end
        return normalised_rows(qs, qss, None, a_end, qss_end, None, self.limit)


class TorqueConstraint(toppra.constraint.JointTorqueConstraint):
    """The joint torque constraint of toppra, discretised like the acceleration one.

    toppra computes the coefficients at each gridpoint by inverse dynamics (build it
    with its collocation scheme); the rows for the interval ends are added here, with
    left limits at curvature jumps, and every row is normalised.
    """

    def compute_constraint_params(self, path: Any, gridpoints: FloatArray) -> tuple:
        """Toppra's torque rows plus interval-end rows, each normalised."""
        grid = np.asarray(gridpoints, dtype=float)
        a, b, c = super().compute_constraint_params(path, grid)[:3]
        b_end = b[1:].copy()
        zero = np.zeros(self.dof)
        for row, _, q, qs, left in jump_rows(path, grid):
            b_end[row] = self.inv_dyn(q, qs, left) - self.inv_dyn(q, zero, zero)
        a_end = a[1:] + 2.0 * np.diff(grid)[:, None] * b_end
        return normalised_rows(a, b, c, a_end, b_end, c[1:], self.tau_lim[:, 1])


class ConstAccelOutput(toppra.parametrizer.ParametrizeConstAccel):
    """toppra's ``ParametrizeConstAccel`` output, its grid times computed with NumPy."""

    def _process_parametrization(self) -> None:
        ds = np.diff(self._ss)
        self._us = 0.5 * np.diff(self._xs) / ds
        speeds = self._velocities[:-1] + self._velocities[1:]
        self._ts = np.concatenate([[0.0], np.cumsum(2.0 * ds / speeds)])


#: The TOPPRA algorithm the planner runs.
TOPPRA = SeidelTOPPRA
