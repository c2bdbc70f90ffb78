"""Tests of controllers.plant: the state, face and checks that every simulated robot shares."""

from __future__ import annotations

import pickle

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot
from plant_support import ROBOTS, alternating_command, inertia_by_rnea

from optraj.controllers.plants import (
    DynamicPlant,
    KinematicPlant,
    Plant,
    PlantState,
    tool_force_to_joint_velocity,
)
from optraj.errors import InvalidInputError, OptrajError


def test_the_base_plants_record_nothing_more():
    robot = get_robot("paddle4")
    for plant in (KinematicPlant(robot), DynamicPlant(robot)):
        assert plant.record() == {}


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


def test_bad_reset_and_helper_input():
    robot = get_robot("sawyer")
    plant = KinematicPlant(robot)
    with pytest.raises(InvalidInputError, match="q"):
        plant.reset(np.zeros(6))
    with pytest.raises(InvalidInputError, match="qd"):
        plant.reset(robot.home, [np.inf] * 7)
    with pytest.raises(InvalidInputError, match="impulse"):
        tool_force_to_joint_velocity(robot, robot.home, [1.0, 2.0])


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


def test_a_plant_needs_a_robot():
    with pytest.raises(InvalidInputError, match="robot"):
        KinematicPlant("sawyer")
