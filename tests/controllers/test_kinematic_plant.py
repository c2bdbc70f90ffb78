"""Tests of controllers.kinematic_plant: ideal velocity servos as exact first-order lags."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from plant_support import ROBOTS, alternating_command
from scipy.integrate import solve_ivp

from optraj.controllers.kinematic_plant import KinematicPlant
from optraj.controllers.plant import tool_force_to_joint_velocity
from optraj.errors import InvalidInputError


@pytest.mark.parametrize("name", ROBOTS)
def test_kinematic_matches_closed_form_lag_with_uneven_steps(name):
    robot = get_robot(name)
    T = 0.005
    plant = KinematicPlant(robot, time_constant=T)
    u = alternating_command(robot, 0.4)
    q0 = robot.home
    plant.reset(q0)
    rng = np.random.default_rng(3)
    t = 0.0
    for dt in rng.uniform(2e-4, 3e-3, size=100):  # exact discretisation: step sizes don't matter
        state = plant.step(u, float(dt))
        t += dt
        decay = np.exp(-t / T)
        np.testing.assert_allclose(state.qd, u * (1.0 - decay), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(
            state.q, q0 + u * t - u * T * (1.0 - decay), rtol=1e-10, atol=1e-12
        )
    assert t > 20 * T  # the lag has settled by the end
    np.testing.assert_allclose(state.qd, u, rtol=1e-8)


def test_kinematic_zero_time_constant_tracks_exactly():
    robot = get_robot("sawyer")
    plant = KinematicPlant(robot, time_constant=0.0)
    plant.reset(robot.home, qd=alternating_command(robot, -0.3))
    u = alternating_command(robot, 0.2)
    for k in range(1, 11):
        state = plant.step(u, 1e-3)
        np.testing.assert_array_equal(state.qd, u)
        np.testing.assert_allclose(state.q, robot.home + u * k * 1e-3, rtol=0, atol=1e-14)


def test_kinematic_matches_ode_solution_for_random_commands():
    # Seeded stress test against scipy's integration of qdd = (u - qd) / T.
    robot = get_robot("sawyer")
    rng = np.random.default_rng(11)
    n = robot.dof
    for _ in range(5):
        T = rng.uniform(1e-3, 2e-2)
        plant = KinematicPlant(robot, time_constant=T)
        q = robot.random_configurations(1, rng)[0]
        qd = rng.uniform(-1.0, 1.0, n) * robot.limits.velocity
        plant.reset(q, qd)
        x = np.concatenate([q, qd])
        for _ in range(8):
            u = rng.uniform(-1.0, 1.0, n) * robot.limits.velocity
            dt = float(rng.uniform(1e-4, 1e-2))
            state = plant.step(u, dt)
            sol = solve_ivp(
                lambda _t, y, u=u, T=T: np.concatenate([y[n:], (u - y[n:]) / T]),
                (0.0, dt),
                x,
                method="DOP853",
                rtol=1e-11,
                atol=1e-13,
            )
            x = sol.y[:, -1]
            np.testing.assert_allclose(state.q, x[:n], rtol=0, atol=1e-9)
            np.testing.assert_allclose(state.qd, x[n:], rtol=0, atol=1e-8)


@pytest.mark.parametrize("name", ROBOTS)
def test_kinematic_reports_inverse_dynamics_of_the_motion(name):
    robot = get_robot(name)
    plant = KinematicPlant(robot)
    before = plant.reset(robot.home)
    after = plant.step(alternating_command(robot, 0.5), 2e-3)
    np.testing.assert_allclose(after.qdd, (after.qd - before.qd) / 2e-3, rtol=1e-12)
    expected = robot.inverse_dynamics(after.q, after.qd, after.qdd)
    np.testing.assert_allclose(after.tau, expected, rtol=1e-12, atol=1e-12)
    assert np.abs(after.qdd).max() > 1.0  # a real acceleration was reported
    assert after.saturated is False


def test_kinematic_impulse_then_lag():
    robot = get_robot("sawyer")
    T, dt = 0.005, 1e-3
    force = np.array([40.0, -25.0, 60.0])
    plant = KinematicPlant(robot, time_constant=T)
    plant.reset(robot.home)
    state = plant.step(np.zeros(robot.dof), dt, tool_force=force)
    jump = tool_force_to_joint_velocity(robot, robot.home, force * dt)
    np.testing.assert_allclose(state.qd, jump * np.exp(-dt / T), rtol=1e-12)
    np.testing.assert_allclose(
        state.q, robot.home + jump * T * (1.0 - np.exp(-dt / T)), rtol=1e-12, atol=1e-15
    )


def test_kinematic_ignores_the_feed_forward_torque():
    robot = get_robot("paddle4")
    u = alternating_command(robot, 0.3)
    force = np.array([2.0, -1.0, 3.0])
    plain, pushed = KinematicPlant(robot), KinematicPlant(robot)
    plain.reset(robot.home)
    pushed.reset(robot.home)
    torque = np.full(robot.dof, 50.0)
    for _ in range(5):
        a = plain.step(u, 1e-3, tool_force=force)
        b = pushed.step(u, 1e-3, tool_force=force, torque=torque)
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)


def test_name():
    assert KinematicPlant(get_robot("sawyer")).name == "kinematic"


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda r: KinematicPlant(r, time_constant=-0.001), "time_constant"),
        (lambda r: KinematicPlant(r, time_constant=float("nan")), "time_constant"),
    ],
)
def test_bad_construction(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build(get_robot("sawyer"))
