"""The grid TOPPRA solves on: gridpoints along the path, refined where limits are exceeded.

:func:`grid_for` spreads the grid intervals over the path's segments so that every knot is a
gridpoint; :func:`refined` splits chosen intervals; :func:`stretch_factor` gives the factor on
the path parameter under which a short path is solved, to keep toppra's numbers at its scale.

Example::

    grid = grid_for(path, 200)          # about 200 intervals, shape (201,)
    c = stretch_factor(path)            # solve in the parameter c s (1 for paths >= 1 unit)
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from optraj.planners.time_optimal.toppra_path import GeometricPath, segment_of
from optraj.planners.time_optimal.toppra_problem import ToppraProblem

__all__ = ["grid_for", "refined", "stretch_factor"]

FloatArray = NDArray[np.float64]

#: Default grid: one interval per this much joint-space path length [rad or m] ...
_GRID_STEP = 0.02
#: ... but no fewer and no more intervals than these.
_MIN_GRID = 100
_MAX_GRID = 400
#: Paths shorter than this many path units are solved in a stretched parameter (see
#: :func:`stretch_factor`).
_STRETCH_BELOW = 1.0


def grid_for(path: GeometricPath, intervals: int | None) -> FloatArray:
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


def refined(problem: ToppraProblem, intervals: NDArray[np.intp]) -> ToppraProblem:
    """The problem with each of the given grid intervals split into four."""
    grid = problem.grid
    inner = grid[intervals, None] + np.diff(grid)[intervals, None] * np.array([0.25, 0.5, 0.75])
    finer = np.sort(np.concatenate([grid, inner.ravel()]))
    return dataclasses.replace(
        problem, grid=finer, segment=segment_of(problem.path.knots, finer[:-1])
    )


def stretch_factor(path: GeometricPath) -> float:
    """Factor c >= 1 on the path parameter that brings a short path's numbers to toppra's scale.

    toppra's Seidel solver tests feasibility with absolute tolerances (1e-10, 1e-8; see
    :func:`~planners.time_optimal.toppra_constraints.normalised_rows`) and caps values at 1e8
    (``toppra.constants.VERYLARGE``). Along a path of length L at a path acceleration bound
    a, the squared path velocity is about a L in the middle and 2 a ds near a rest end
    (ds = L / N the grid step), so on a very short path it falls below those tolerances and
    toppra calls the controllable set empty. In the parameter c s squared path velocities
    grow by c^2 and path accelerations by c; c = 1 / sqrt(L) makes the squared path
    velocities of order a (a L c^2 = a, 2 a / N at the ends) and keeps the path
    accelerations, a / sqrt(L), below the cap for any L above STILL_TOLERANCE (c = 1 / L
    would push them into the cap). Paths at least one unit long are solved as they are.
    """
    span = float(path.knots[-1] - path.knots[0])
    return 1.0 / math.sqrt(span) if 0.0 < span < _STRETCH_BELOW else 1.0
