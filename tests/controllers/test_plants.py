"""Tests of controllers.plants: the kinematic and dynamic simulated robots."""

from __future__ import annotations

import pickle

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot
from scipy.integrate import solve_ivp

from optraj.controllers.controller import sample_references
from optraj.controllers.plants import (
    DynamicPlant,
    KinematicPlant,
    Plant,
    PlantState,
    tool_force_to_joint_velocity,
)
from optraj.errors import InvalidInputError, OptrajError
from optraj.planners.trajectory import Trajectory

ROBOTS = ("sawyer", "paddle4")  # paddle4's first joint is prismatic


def alternating_command(robot, fraction):
    """A joint velocity command at ``fraction`` of the limits with alternating signs."""
    signs = np.where(np.arange(robot.dof) % 2 == 0, 1.0, -1.0)
    return fraction * robot.limits.velocity * signs


def inertia_by_rnea(robot, q):
    """Joint-space inertia matrix from RNEA columns: M e_j = rnea(q, 0, e_j) - g(q)."""
    n = robot.dof
    zeros = np.zeros(n)
    gravity = robot.inverse_dynamics(q, zeros, zeros)
    return np.column_stack([robot.inverse_dynamics(q, zeros, e) - gravity for e in np.eye(n)])


# ------------------------------------------------------------------------------ KinematicPlant


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


# -------------------------------------------------------------------------------- DynamicPlant


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


def test_the_base_plants_record_nothing_more():
    robot = get_robot("paddle4")
    for plant in (KinematicPlant(robot), DynamicPlant(robot)):
        assert plant.record() == {}


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


# ------------------------------------------------------------------------------ tool impulses


@pytest.mark.parametrize("name", ROBOTS)
def test_impulse_response_balances_momentum_and_energy(name):
    robot = get_robot(name)
    rng = np.random.default_rng(7)
    for q in robot.random_configurations(10, rng):
        impulse = rng.normal(size=3) * 0.5
        dqd = tool_force_to_joint_velocity(robot, q, impulse)
        J = robot.jacobian(q)[:3]
        # Momentum balance: M dqd = J^T p, with M from RNEA (not CRBA).
        M = inertia_by_rnea(robot, q)
        np.testing.assert_allclose(M @ dqd, J.T @ impulse, rtol=1e-9, atol=1e-12)
        # From rest, the kinetic energy gained is half the impulse times the tool's new speed.
        energy = pin.computeKineticEnergy(robot.model, robot.model.createData(), q, dqd)
        np.testing.assert_allclose(energy, 0.5 * impulse @ (J @ dqd), rtol=1e-9)
        assert energy > 0.0


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


# ------------------------------------------------------------------------------ state and input


def test_reset_sets_state_and_owns_its_arrays():
    robot = get_robot("paddle4")
    q = robot.home.copy()
    qd = np.array([0.1, -0.2, 0.3, -0.4])
    for plant in (KinematicPlant(robot), DynamicPlant(robot)):
        state = plant.reset(q, qd)
        assert isinstance(state, PlantState)
        assert isinstance(plant, Plant)
        q_saved = q.copy()
        q[0] += 1.0  # changing the caller's array must not change the plant
        np.testing.assert_array_equal(plant.state.q, q_saved)
        q[0] -= 1.0
        np.testing.assert_array_equal(plant.state.qd, qd)
        np.testing.assert_array_equal(plant.state.qdd, 0.0)
        np.testing.assert_array_equal(plant.state.tau, 0.0)
        assert plant.state.saturated is False
        with pytest.raises(ValueError, match="read-only"):
            plant.state.q[0] = 5.0
        np.testing.assert_array_equal(plant.reset(q).qd, 0.0)


def test_names():
    robot = get_robot("sawyer")
    assert KinematicPlant(robot).name == "kinematic"
    assert DynamicPlant(robot).name == "dynamic"


@pytest.mark.parametrize("plant_type", [KinematicPlant, DynamicPlant])
def test_step_or_state_before_reset_is_an_error(plant_type):
    robot = get_robot("sawyer")
    plant = plant_type(robot)
    with pytest.raises(InvalidInputError, match="reset"):
        plant.step(np.zeros(robot.dof), 1e-3)
    with pytest.raises(OptrajError, match="reset"):
        _ = plant.state


@pytest.mark.parametrize("plant_type", [KinematicPlant, DynamicPlant])
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"command": np.zeros(6)}, "command"),
        ({"command": [[0.0] * 7]}, "command"),
        ({"command": [0.0] * 6 + [np.nan]}, "command"),
        ({"command": ["a"] * 7}, "command"),
        ({"dt": 0.0}, "dt"),
        ({"dt": -1e-3}, "dt"),
        ({"dt": float("inf")}, "dt"),
        ({"tool_force": [np.nan, 0.0, 0.0]}, "tool_force"),
        ({"tool_force": [1.0, 0.0]}, "tool_force"),
        ({"torque": np.zeros(6)}, "torque"),
        ({"torque": np.zeros((1, 7))}, "torque"),
        ({"torque": [0.0] * 6 + [np.inf]}, "torque"),
        ({"torque": ["a"] * 7}, "torque"),
        ({"torque": np.zeros(7, dtype=np.float32) + np.nan}, "torque"),
    ],
)
def test_bad_step_input(plant_type, kwargs, match):
    robot = get_robot("sawyer")
    plant = plant_type(robot)
    plant.reset(robot.home)
    args = {"command": np.zeros(7), "dt": 1e-3, "tool_force": None, "torque": None} | kwargs
    with pytest.raises(InvalidInputError, match=match):
        plant.step(**args)
    np.testing.assert_array_equal(plant.state.q, robot.home)  # a refused step changes nothing


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda r: KinematicPlant(r, time_constant=-0.001), "time_constant"),
        (lambda r: KinematicPlant(r, time_constant=float("nan")), "time_constant"),
        (lambda r: DynamicPlant(r, bandwidth=0.0), "bandwidth"),
        (lambda r: DynamicPlant(r, max_substep=-1.0), "max_substep"),
        (lambda r: DynamicPlant(r, saturate="yes"), "saturate"),
        (lambda r: KinematicPlant("sawyer"), "robot"),
    ],
)
def test_bad_construction(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build(get_robot("sawyer"))


def test_bad_reset_and_helper_input():
    robot = get_robot("sawyer")
    plant = KinematicPlant(robot)
    with pytest.raises(InvalidInputError, match="q"):
        plant.reset(np.zeros(6))
    with pytest.raises(InvalidInputError, match="qd"):
        plant.reset(robot.home, [np.inf] * 7)
    with pytest.raises(InvalidInputError, match="impulse"):
        tool_force_to_joint_velocity(robot, robot.home, [1.0, 2.0])


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


@pytest.mark.parametrize(
    "build",
    [lambda r: KinematicPlant(r), lambda r: DynamicPlant(r)],
    ids=["kinematic", "dynamic"],
)
@pytest.mark.parametrize("name", ROBOTS)
def test_pickle_round_trip_steps_identically(build, name):
    robot = get_robot(name)
    plant = build(robot)
    plant.reset(robot.home)
    u = alternating_command(robot, 0.3)
    for _ in range(3):
        plant.step(u, 1e-3)
    copy = pickle.loads(pickle.dumps(plant))
    np.testing.assert_array_equal(copy.state.q, plant.state.q)
    force = np.array([1.0, 2.0, -3.0])
    for _ in range(3):
        a = plant.step(u, 1e-3, tool_force=force)
        b = copy.step(u, 1e-3, tool_force=force)
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)
