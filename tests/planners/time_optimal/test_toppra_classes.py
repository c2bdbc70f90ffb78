"""Tests of optraj.planners.time_optimal.toppra_classes: toppra-derived classes, plain classes."""

from __future__ import annotations

import pickle
import subprocess
import sys

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.planners import Toppra
from optraj.planners.time_optimal import toppra_classes
from optraj.planners.time_optimal.toppra_path import GeometricPath


def test_a_plan_holds_the_module_classes_by_their_own_names():
    robot = get_robot("paddle4")
    traj = Toppra().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.2))
    native = traj.metadata["native"]
    assert type(native) is toppra_classes.ConstAccelOutput
    assert type(native).__module__ == "optraj.planners.time_optimal.toppra_classes"
    assert type(native).__qualname__ == "ConstAccelOutput"  # no renaming, no module hook


def test_the_polynomial_path_passes_its_waypoints_with_its_derivatives():
    waypoints = np.array([[0.0, 0.0], [0.5, -0.2], [1.0, 0.4], [1.2, 0.1]])
    path = GeometricPath.pchip(waypoints)
    native = toppra_classes.PolynomialPath(path)
    assert native.dof == 2
    np.testing.assert_allclose(native.path_interval, [path.knots[0], path.knots[-1]])
    np.testing.assert_allclose(native(path.knots), waypoints, atol=1e-12)
    s = np.linspace(path.knots[0], path.knots[-1], 41)
    step = 1e-6
    slope = (native(s[1:-1] + step) - native(s[1:-1] - step)) / (2 * step)
    np.testing.assert_allclose(native(s[1:-1], 1), slope, atol=1e-6)


def test_the_speed_constraint_bounds_the_squared_path_speed_by_its_rates():
    path = toppra_classes.PolynomialPath(GeometricPath.line(np.zeros(2), np.array([0.3, 0.4])))

    def rates(_path, s):  # a joint speed cap of 2 per unit path speed, everywhere
        return np.full((len(s), 1), 2.0)

    xbound = toppra_classes.SpeedConstraint(rates, 2).compute_constraint_params(
        path, np.linspace(0.0, 0.5, 6)
    )[-1]
    np.testing.assert_allclose(xbound[:, 0], 0.0)
    assert xbound[:, 1] == pytest.approx(np.full(6, 0.25))  # x = sd^2 <= 1 / 2^2


@pytest.mark.slow
def test_results_pickle_with_toppras_object():
    robot = get_robot("paddle4")
    problem = problems.Waypoints(robot, robot.random_configurations(3, np.random.default_rng(4)))
    traj = Toppra().plan(problem)
    clone = pickle.loads(pickle.dumps(traj))
    t = np.linspace(0.0, traj.duration, 50)
    np.testing.assert_array_equal(clone.sample(t).q, traj.sample(t).q)
    np.testing.assert_allclose(clone.metadata["native"](t), traj.sample(t).q, atol=1e-9)
    assert clone.metadata["controllable_sets"].shape == (traj.metadata["gridpoints"] + 1, 2)
    # a fresh interpreter finds the toppra-derived classes too
    code = (
        "import pickle, sys; traj = pickle.loads(sys.stdin.buffer.read()); "
        "print(traj.metadata['native'].duration)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], input=pickle.dumps(traj), capture_output=True, check=False
    )
    assert done.returncode == 0, done.stderr.decode()
    assert float(done.stdout) == pytest.approx(traj.duration)
