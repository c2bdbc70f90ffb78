from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.controllers.controller import Command, Reference, State
from optraj.controllers.joint_pd import JointPD
from optraj.errors import InvalidInputError


def _reference(robot, q, qd):
    return Reference(0.0, q, qd, np.zeros(robot.dof), np.eye(4), np.zeros(6), "")


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_law_with_per_joint_gains(name):
    robot = get_robot(name)
    rng = np.random.default_rng(41)
    kp = rng.uniform(1.0, 30.0, robot.dof)
    kd = rng.uniform(0.0, 2.0, robot.dof)
    controller = JointPD(robot, kp=kp, kd=kd)
    for _ in range(20):
        q, q_ref = robot.random_configurations(2, rng)
        qd, qd_ref = rng.normal(size=(2, robot.dof))
        command = controller.step(State(0.0, q, qd), _reference(robot, q_ref, qd_ref), 1e-3)
        assert isinstance(command, Command)
        assert command.status == "ok"
        expected = np.array(
            [
                qd_ref[j] + kp[j] * (q_ref[j] - q[j]) + kd[j] * (qd_ref[j] - qd[j])
                for j in range(robot.dof)
            ]
        )
        np.testing.assert_allclose(command.qd, expected, rtol=1e-14, atol=1e-14)


def test_hand_computed_command_with_scalar_gains():
    robot = get_robot("paddle4")
    controller = JointPD(robot, kp=10.0, kd=0.5)
    np.testing.assert_array_equal(controller.kp, np.full(4, 10.0))
    np.testing.assert_array_equal(controller.kd, np.full(4, 0.5))
    q = np.array([0.5, 0.1, 0.2, 0.0])
    qd = np.array([0.0, 1.0, 0.0, -1.0])
    reference = _reference(robot, np.array([0.6, 0.1, 0.1, 0.2]), np.array([0.2, 0.0, 0.0, 1.0]))
    command = controller.step(State(0.0, q, qd), reference, 1e-3)
    # 0.2 + 10 * 0.1 + 0.5 * 0.2, 0 + 0 + 0.5 * -1, 0 + 10 * -0.1 + 0, 1 + 10 * 0.2 + 0.5 * 2
    np.testing.assert_allclose(command.qd, [1.3, -0.5, -1.0, 4.0], rtol=0, atol=1e-14)


def test_on_reference_command_is_feed_forward_and_memoryless():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(42)
    controller = JointPD(robot, kp=20.0, kd=1.0)
    q = robot.random_configurations(1, rng)[0]
    qd = rng.normal(size=robot.dof)
    state, reference = State(0.0, q, qd), _reference(robot, q, qd)
    np.testing.assert_array_equal(controller.step(state, reference, 1e-3).qd, qd)
    controller.reset(state)
    np.testing.assert_array_equal(controller.step(state, reference, 0.5).qd, qd)  # dt unused
    assert controller.name == "joint PD"


def test_the_command_carries_the_plans_feed_forward_torque():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(43)
    q, q_ref = robot.random_configurations(2, rng)
    qd, qd_ref, tau = rng.normal(size=(3, robot.dof))
    state = State(0.0, q, qd)
    reference = _reference(robot, q_ref, qd_ref)._replace(tau=tau)
    with_torque = JointPD(robot, kd=0.5).step(state, reference, 1e-3)
    without = JointPD(robot, kd=0.5, feedforward=False).step(state, reference, 1e-3)
    np.testing.assert_array_equal(with_torque.tau, tau)
    assert without.tau is None
    np.testing.assert_array_equal(with_torque.qd, without.qd)
    assert JointPD(robot).step(state, reference._replace(tau=None), 1e-3).tau is None
    with pytest.raises(InvalidInputError, match=r"feedforward must be True or False"):
        JointPD(robot, feedforward="no")  # type: ignore[arg-type]


def test_gain_errors():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match=r"kp must be a scalar or one gain per joint \(7\)"):
        JointPD(robot, kp=np.ones(4))
    with pytest.raises(InvalidInputError, match=r"kd must be a scalar or one gain per joint.*8"):
        JointPD(robot, kd=np.ones(8))
    with pytest.raises(InvalidInputError, match=r"kp must be >= 0"):
        JointPD(robot, kp=-1.0)
    with pytest.raises(InvalidInputError, match=r"kd must be >= 0"):
        JointPD(robot, kd=[0.1, 0.1, 0.1, -0.1, 0.1, 0.1, 0.1])
    with pytest.raises(InvalidInputError, match=r"kp must be finite"):
        JointPD(robot, kp=np.inf)
    with pytest.raises(InvalidInputError, match=r"kp must have shape"):
        JointPD(robot, kp=np.ones((7, 1)))


def test_a_robot_that_is_not_a_robot_is_refused():
    with pytest.raises(InvalidInputError, match=r"robot must be a robots\.Robot"):
        JointPD("sawyer")  # not an AttributeError on .dof
