"""Tests of planners.time_optimal.toppra_path: geometric paths as piecewise polynomials."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from scipy.interpolate import CubicSpline, PchipInterpolator

from optraj import planners, problems
from optraj.planners.time_optimal.toppra_path import (
    GeometricPath,
    curvature_jumps,
    derivative,
    polyval_grid,
    polyval_local,
    segment_of,
    toppra_classes,
)


def test_a_stretched_path_is_the_same_path():
    path = GeometricPath.spline(np.array([[0.0, 0.0], [1e-3, 2e-3], [3e-3, 1e-3]]))
    stretched = path.stretched(500.0)
    s = np.linspace(0.0, path.knots[-1], 7)
    for order in range(3):
        np.testing.assert_allclose(
            stretched.native(500.0 * s, order) * 500.0**order, path.native(s, order), rtol=1e-12
        )


def test_pchip_slopes_near_zero_stay_finite_without_overflow_warnings():
    import warnings

    from optraj.planners.time_optimal.toppra_planner import GeometricPath

    waypoints = np.array([[0.0, 0.0], [1.0, 1e-310], [2.0, 2e-310], [3.0, 0.5]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow in the slopes' mean would warn
        path = GeometricPath.pchip(waypoints)
    assert np.all(np.isfinite(path.coefficients))


def test_the_spline_and_the_pchip_are_scipys():
    rng = np.random.default_rng(9)
    for k in (2, 3, 4, 6):
        waypoints = rng.uniform(-1.0, 1.0, (k, 3))
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))])
        fine = np.linspace(0.0, s[-1], 301)
        for path, reference in (
            (GeometricPath.spline(waypoints), CubicSpline(s, waypoints)),
            (GeometricPath.pchip(waypoints), PchipInterpolator(s, waypoints)),
        ):
            np.testing.assert_allclose(path.knots, s, rtol=1e-15)
            for order in range(3):
                np.testing.assert_allclose(
                    path.native(fine, order), reference(fine, order), rtol=0, atol=1e-9
                )


def test_the_line_and_a_trajectory_as_paths():
    line = GeometricPath.line(np.array([0.0, 1.0]), np.array([0.3, 1.4]))
    np.testing.assert_allclose(line.knots, [0.0, 0.5])
    np.testing.assert_allclose(line.native(np.array([0.25])), [[0.15, 1.2]], rtol=1e-15)
    assert line.length == pytest.approx(0.5, rel=1e-15) and line.dof == 2 and line.unit == "rad"
    robot = get_robot("paddle4")
    q1 = robot.home + 0.2
    go = planners.Quintic().plan(problems.PointToPoint(robot, robot.home, q1))
    back = planners.Quintic().plan(problems.PointToPoint(robot, q1, robot.home))
    path = GeometricPath.from_trajectory(go.then(back))
    assert path.unit == "s" and path.kind.startswith("trajectory from 'quintic'")
    np.testing.assert_allclose(path.rest_points, [go.duration])  # at rest between the moves
    assert line.rest_points.size == 0


def test_polynomial_helpers_evaluate_and_differentiate():
    # two segments of one joint: 1 + 2 x + 3 x^2 on [0, 1), 6 + 8 x on [1, 2]
    coefficients = np.array([[[1.0], [2.0], [3.0]], [[6.0], [8.0], [0.0]]])
    knots = np.array([0.0, 1.0, 2.0])
    np.testing.assert_array_equal(derivative(coefficients)[:, :, 0], [[2.0, 6.0], [8.0, 0.0]])
    np.testing.assert_array_equal(derivative(coefficients[:, :1]), np.zeros((2, 1, 1)))
    np.testing.assert_allclose(
        polyval_local(coefficients, np.array([0.5, 0.25]))[:, 0], [2.75, 8.0]
    )
    values = polyval_grid(coefficients, np.array([[0.0, 1.0], [0.0, 0.5]]))
    np.testing.assert_allclose(values[:, :, 0], [[1.0, 6.0], [6.0, 10.0]])
    np.testing.assert_array_equal(segment_of(knots, np.array([0.0, 0.5, 1.0, 2.0])), [0, 0, 1, 1])


def test_curvature_jumps_of_a_pchip_but_not_of_a_spline():
    waypoints = np.array([[0.0, 0.0], [0.5, -0.2], [1.0, 0.4], [1.2, 0.1]])
    spline = GeometricPath.spline(waypoints)
    assert curvature_jumps(spline.knots, spline.coefficients)[0].size == 0  # C2
    pchip = GeometricPath.pchip(waypoints)
    s, q, qs, left = curvature_jumps(pchip.knots, pchip.coefficients)
    assert s.size > 0 and set(s) <= set(pchip.knots[1:-1])
    np.testing.assert_allclose(q, pchip.native(s), atol=1e-12)
    np.testing.assert_allclose(qs, pchip.native(s, 1), atol=1e-12)
    np.testing.assert_allclose(left, pchip.native(s - 1e-9, 2), atol=1e-5)  # before the knot


def test_toppra_classes_is_the_module_of_the_toppra_derived_classes():
    from optraj.planners.time_optimal import toppra_classes as module

    assert toppra_classes() is module
    path = GeometricPath.line(np.zeros(2), np.array([0.3, 0.4]))
    assert type(path.native) is module.PolynomialPath
