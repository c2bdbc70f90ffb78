import numpy as np
import pytest

from optraj import controllers, physics, robots
from optraj.errors import InvalidInputError

FAR_BALL = (0.75, 0.15, -0.6)  # well away from anything the arm does here


@pytest.fixture(scope="module")
def sawyer():
    return robots.load("sawyer")


def _run(plant, robot, seconds=1.0, dt=1e-3):
    t = np.arange(0.0, seconds, dt)
    amplitude = 0.3 * robot.limits.velocity
    state = plant.reset(robot.home)
    path = [state.q]
    for time in t:
        command = amplitude * np.sin(2 * np.pi * 0.5 * time + np.arange(robot.dof))
        state = plant.step(command, dt)
        path.append(state.q)
    return np.array(path)


def test_mujoco_and_pinocchio_plants_agree_on_a_contact_free_motion(sawyer):
    # Same URDF, same servo law, same torques: the two integrators differ by round-off and
    # by MuJoCo's implicit damping; over 1 s the joints stay within 2 mrad.
    mujoco_path = _run(physics.MujocoPlant(physics.pool_scene(sawyer, FAR_BALL)), sawyer)
    dynamic_path = _run(controllers.DynamicPlant(sawyer), sawyer)
    assert np.abs(mujoco_path - dynamic_path).max() < 2e-3
    assert np.abs(mujoco_path[-1] - mujoco_path[0]).max() > 0.05  # it did move


def test_the_feed_forward_torque_reaches_the_arm(sawyer):
    torque = np.zeros(7)
    torque[3] = 2.0
    speeds = []
    for plant in (
        physics.MujocoPlant(physics.pool_scene(sawyer, FAR_BALL)),
        controllers.DynamicPlant(sawyer),
    ):
        plant.reset(sawyer.home)
        speeds.append(plant.step(np.zeros(7), 1e-3, torque=torque).qd)
    assert speeds[0][3] > 0.0
    # Over one 1 ms step the stiff servo modes (b * lambda up to 4800 1/s) are damped more by
    # MuJoCo's implicit integration than by semi-implicit Euler: 10 to 18 % less speed here.
    np.testing.assert_allclose(speeds[0], speeds[1], rtol=0.25, atol=1e-4)


def test_plant_pickles_and_rebuilds(sawyer):
    import pickle

    plant = physics.MujocoPlant(physics.pool_scene(sawyer, FAR_BALL))
    copy = pickle.loads(pickle.dumps(plant))
    a = _run(plant, sawyer, seconds=0.05)
    b = _run(copy, sawyer, seconds=0.05)
    np.testing.assert_array_equal(a, b)


def test_a_kinematic_scene_cannot_be_a_plant(sawyer):
    with pytest.raises(InvalidInputError, match="kinematic"):
        physics.MujocoPlant(physics.pool_scene(sawyer, FAR_BALL, kinematic=True))


def test_bad_torque_is_a_typed_error(sawyer):
    plant = physics.MujocoPlant(physics.pool_scene(sawyer, FAR_BALL))
    plant.reset(sawyer.home)
    with pytest.raises(InvalidInputError, match="torque"):
        plant.step(np.zeros(7), 1e-3, torque=np.full(7, np.nan))
