"""Tests of controllers.dynamic_plant: rigid-body dynamics under a velocity servo per joint."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from plant_support import ROBOTS, alternating_command, inertia_by_rnea
from scipy.integrate import solve_ivp

from optraj.controllers.controller import sample_references
from optraj.controllers.dynamic_plant import DynamicPlant
from optraj.controllers.kinematic_plant import KinematicPlant
from optraj.controllers.plant import tool_force_to_joint_velocity
from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Trajectory


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_initial_acceleration_is_the_servo_law(name):
    # From rest with gravity compensated, the first substep accelerates by M^-1 b diag(M) u.
    robot = get_robot(name)
    bandwidth, dt = 200.0, 1e-6
    plant = DynamicPlant(robot, bandwidth=bandwidth, saturate=False)
    plant.reset(robot.home)
    u = alternating_command(robot, 0.3)
    state = plant.step(u, dt)
    M = inertia_by_rnea(robot, robot.home)
    expected = np.linalg.solve(M, bandwidth * np.diag(M) * u)
    np.testing.assert_allclose(state.qdd, expected, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(
        state.tau, robot.gravity_torque(robot.home) + bandwidth * np.diag(M) * u, rtol=1e-9
    )


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_adds_the_feed_forward_torque_to_the_servo(name):
    # From rest, the first substep's torque is g + tau_ff + b diag(M) u, its acceleration
    # M^-1 (tau_ff + b diag(M) u).
    robot = get_robot(name)
    bandwidth, dt = 200.0, 1e-6
    rng = np.random.default_rng(8)
    torque = rng.normal(0.0, 1.0, robot.dof) * 0.1 * robot.limits.effort
    u = alternating_command(robot, 0.3)
    plant = DynamicPlant(robot, bandwidth=bandwidth, saturate=False)
    plant.reset(robot.home)
    state = plant.step(u, dt, torque=torque)
    M = inertia_by_rnea(robot, robot.home)
    servo = bandwidth * np.diag(M) * u
    np.testing.assert_allclose(state.qdd, np.linalg.solve(M, torque + servo), rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(
        state.tau, robot.gravity_torque(robot.home) + torque + servo, rtol=1e-9, atol=1e-9
    )
    # No torque is a zero torque; a list or float32 torque is the same torque.
    ends = []
    for feedforward in (None, np.zeros(robot.dof), torque, list(torque), torque.astype(np.float32)):
        plant.reset(robot.home)
        ends.append(plant.step(u, 1e-3, torque=feedforward).q)
    np.testing.assert_array_equal(ends[1], ends[0])
    np.testing.assert_array_equal(ends[3], ends[2])
    np.testing.assert_allclose(ends[4], ends[2], rtol=0, atol=1e-9)
    assert np.abs(ends[2] - ends[0]).max() > 1e-6  # the torque moves the arm


def test_feed_forward_of_the_inverse_dynamics_tracks_a_motion_closely():
    # A smooth Sawyer motion (up to 54 % of the speed limits), commanded with its own joint
    # velocity at the start of every 1 ms step: the servo alone lags it by 0.032 rad; with
    # the motion's inverse dynamics less gravity fed forward the lag is 90 times smaller
    # (measured 0.032 rad against 3.5e-4 rad).
    robot = get_robot("sawyer")
    step = 2.0 * np.array([0.25, -0.2, 0.3, 0.15, -0.3, 0.2, 0.4])
    q = np.stack([robot.home, robot.home + step, robot.home + 0.5 * step])
    qd = np.stack([np.zeros(robot.dof), 0.3 * step, np.zeros(robot.dof)])
    motion = Trajectory.from_hermite([0.0, 1.0, 2.0], q, qd, np.zeros_like(q))
    dt = 1e-3
    t = np.arange(2001) * dt
    sample = motion.sample(t)
    torque = robot.inverse_dynamics(sample.q, sample.qd, sample.qdd) - robot.gravity_torque(
        sample.q
    )
    np.testing.assert_allclose(sample_references(robot, motion, t).tau, torque, atol=1e-12)
    errors = {}
    for feedforward in (False, True):
        plant = DynamicPlant(robot)
        plant.reset(sample.q[0], sample.qd[0])
        worst = 0.0
        for k in range(t.size - 1):
            state = plant.step(sample.qd[k], dt, torque=torque[k] if feedforward else None)
            assert not state.saturated
            worst = max(worst, float(np.abs(state.q - sample.q[k + 1]).max()))
        errors[feedforward] = worst
    assert errors[False] > 0.02  # the servo alone really lags
    assert errors[True] < 1e-3
    assert errors[False] / errors[True] > 20.0


def test_dynamic_saturation_includes_the_feed_forward():
    robot = get_robot("sawyer")
    effort = robot.limits.effort
    plant = DynamicPlant(robot)
    plant.reset(robot.home)
    state = plant.step(np.zeros(robot.dof), 1e-3, torque=3.0 * effort)
    assert state.saturated is True
    np.testing.assert_allclose(state.tau, effort, rtol=1e-12)  # every joint clipped above


def test_dynamic_integrates_by_semi_implicit_euler():
    # One substep from rest: the position moves with the new velocity (symplectic Euler),
    # not the old one (explicit Euler would leave it in place).
    robot = get_robot("sawyer")
    plant = DynamicPlant(robot, max_substep=1e-4, saturate=False)
    plant.reset(robot.home)
    state = plant.step(alternating_command(robot, 0.3), 1e-4)
    assert np.abs(state.qd).max() > 1e-3
    np.testing.assert_allclose(state.q - robot.home, 1e-4 * state.qd, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_converges_to_the_command(name):
    robot = get_robot(name)
    plant = DynamicPlant(robot, saturate=False)
    plant.reset(robot.home)
    u = alternating_command(robot, 0.2)
    for _ in range(50):  # 50 ms = 10 servo time constants
        state = plant.step(u, 1e-3)
    # Uncompensated Coriolis forces leave a small steady error (about 2 % measured).
    np.testing.assert_allclose(state.qd, u, rtol=0, atol=0.04 * np.abs(u).max())
    assert not state.saturated


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_holds_its_position_against_gravity(name):
    robot = get_robot(name)
    plant = DynamicPlant(robot, saturate=False)
    plant.reset(robot.home)
    for _ in range(1000):  # 1 s
        state = plant.step(np.zeros(robot.dof), 1e-3)
    np.testing.assert_allclose(state.q, robot.home, rtol=0, atol=1e-9)
    np.testing.assert_allclose(state.qd, 0.0, atol=1e-9)
    gravity = robot.gravity_torque(robot.home)
    assert np.abs(gravity).max() > 1.0  # gravity really acts on this arm
    np.testing.assert_allclose(state.tau, gravity, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize(
    ("name", "speed_tol", "position_tol"), [("sawyer", 0.03, 0.01), ("paddle4", 0.08, 0.05)]
)
def test_dynamic_and_kinematic_agree_on_slow_smooth_commands(name, speed_tol, position_tol):
    # Tolerances: measured 2 % / 0.006 rad (sawyer) and 6 % / 0.03 rad (paddle4's light last
    # joint, disturbed by its inertia coupling with joint 2), with some margin.
    robot = get_robot(name)
    kinematic, dynamic = KinematicPlant(robot), DynamicPlant(robot)
    kinematic.reset(robot.home)
    dynamic.reset(robot.home)
    amplitude = 0.3 * robot.limits.velocity * np.cos(np.arange(robot.dof))
    for k in range(1000):  # 1 s of a 0.5 Hz sine
        u = amplitude * np.sin(np.pi * k * 1e-3)
        a = kinematic.step(u, 1e-3)
        b = dynamic.step(u, 1e-3)
        assert not b.saturated
        np.testing.assert_allclose(b.qd, a.qd, rtol=0, atol=speed_tol * np.abs(amplitude).max())
        np.testing.assert_allclose(b.q, a.q, rtol=0, atol=position_tol)


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_converges_to_the_ode_solution_with_tool_force(name):
    # Independent reference: the continuous closed loop with M and C qd + g from RNEA,
    # integrated by scipy. Semi-implicit Euler is first order: halving the substep must halve
    # the error, and the error must be small.
    robot = get_robot(name)
    n = robot.dof
    bandwidth = 100.0
    force = np.array([5.0, -8.0, 12.0])
    u = alternating_command(robot, 0.3)

    def closed_loop(_t, y):
        q, qd = y[:n], y[n:]
        M = inertia_by_rnea(robot, q)
        servo = robot.gravity_torque(q) + bandwidth * np.diag(M) * (u - qd)
        bias = robot.inverse_dynamics(q, qd, np.zeros(n))
        push = robot.jacobian(q)[:3].T @ force
        return np.concatenate([qd, np.linalg.solve(M, servo + push - bias)])

    start = np.concatenate([robot.home, np.zeros(n)])
    reference = solve_ivp(closed_loop, (0.0, 0.02), start, rtol=1e-10, atol=1e-12).y[:, -1]
    errors = []
    for substep in (2e-5, 1e-5):
        plant = DynamicPlant(robot, bandwidth=bandwidth, max_substep=substep, saturate=False)
        plant.reset(robot.home)
        for _ in range(10):
            state = plant.step(u, 2e-3, tool_force=force)
        errors.append(np.abs(np.concatenate([state.q, state.qd]) - reference).max())
    assert 1.8 < errors[0] / errors[1] < 2.2
    assert errors[1] < 1e-3 * np.abs(u).max()  # measured 2.7e-4 (sawyer), 6.4e-4 (paddle4) of it


@pytest.mark.parametrize("name", ROBOTS)
def test_saturation_clips_torque_to_the_effort_limits(name):
    robot = get_robot(name)
    effort = robot.limits.effort
    huge = alternating_command(robot, 100.0)
    clipped = DynamicPlant(robot, saturate=True)
    clipped.reset(robot.home)
    state = clipped.step(huge, 1e-3)
    assert state.saturated is True
    assert np.all(np.abs(state.tau) <= effort * (1.0 + 1e-12))
    free = DynamicPlant(robot, saturate=False)
    free.reset(robot.home)
    state = free.step(huge, 1e-3)
    assert state.saturated is False
    assert np.any(np.abs(state.tau) > effort)
    kinematic = KinematicPlant(robot)
    kinematic.reset(robot.home)
    assert kinematic.step(huge, 1e-3).saturated is False


def test_small_command_does_not_saturate():
    robot = get_robot("sawyer")
    plant = DynamicPlant(robot)
    plant.reset(robot.home)
    assert plant.step(alternating_command(robot, 0.05), 1e-3).saturated is False


@pytest.mark.parametrize("name", ROBOTS)
def test_dynamic_short_push_matches_the_impulse_response(name):
    robot = get_robot(name)
    dt = 1e-3
    force = np.array([30.0, -20.0, 40.0])
    plant = DynamicPlant(robot, bandwidth=1e-6, saturate=False)
    plant.reset(robot.home)
    state = plant.step(np.zeros(robot.dof), dt, tool_force=force)
    expected = tool_force_to_joint_velocity(robot, robot.home, force * dt)
    # The push lasts dt, not an instant: the arm moves and M(q) changes meanwhile (0.06 %
    # measured).
    np.testing.assert_allclose(state.qd, expected, rtol=0, atol=5e-3 * np.abs(expected).max())
    assert np.abs(expected).max() > 1e-3


def test_too_long_step_and_divergence_are_reported():
    robot = get_robot("sawyer")
    plant = DynamicPlant(robot)
    plant.reset(robot.home)
    with pytest.raises(InvalidInputError, match="substeps"):
        plant.step(np.zeros(7), 1e6)
    # A servo far too stiff for its substep blows up; the error names dt and the substep.
    unstable = DynamicPlant(robot, bandwidth=1e7, saturate=False)
    unstable.reset(robot.home)
    with pytest.raises(InvalidInputError, match="diverged"):
        for _ in range(200):
            unstable.step(alternating_command(robot, 0.1), 1e-3)


def test_name():
    assert DynamicPlant(get_robot("sawyer")).name == "dynamic"


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda r: DynamicPlant(r, bandwidth=0.0), "bandwidth"),
        (lambda r: DynamicPlant(r, max_substep=-1.0), "max_substep"),
        (lambda r: DynamicPlant(r, saturate="yes"), "saturate"),
    ],
)
def test_bad_construction(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build(get_robot("sawyer"))
