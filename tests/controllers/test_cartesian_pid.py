from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from scipy.spatial.transform import Rotation

from optraj.controllers.cartesian_pid import TASKS, CartesianPID, tool_kinematics
from optraj.controllers.controller import Reference
from optraj.errors import InvalidInputError, UnknownNameError

DT = 1e-3


def _pose(R, p):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def _reference(T_desired, twist=None, n=7):
    twist = np.zeros(6) if twist is None else np.asarray(twist, dtype=float)
    zeros = np.zeros(n)
    return Reference(0.0, zeros, zeros, zeros, T_desired, twist, "")


def _measured_pose(seed=3):
    rng = np.random.default_rng(seed)
    R = Rotation.random(random_state=rng).as_matrix()
    return _pose(R, rng.uniform(-0.5, 0.5, 3))


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_tool_kinematics_matches_robot(name):
    robot = get_robot(name)
    rng = np.random.default_rng(7)
    for q in robot.random_configurations(15, rng):
        T, J = tool_kinematics(robot, q)
        assert T.shape == (4, 4)
        assert J.shape == (6, robot.dof)
        np.testing.assert_allclose(T, robot.tool_pose(q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(J, robot.jacobian(q), rtol=0, atol=1e-12)


def test_tool_kinematics_jacobian_matches_finite_difference():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(8)
    q = robot.random_configurations(1, rng)[0]
    _, J = tool_kinematics(robot, q)
    h = 1e-6
    for j in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[j] = h
        Ta, Tb = robot.tool_pose(q + dq), robot.tool_pose(q - dq)
        linear = (Ta[:3, 3] - Tb[:3, 3]) / (2 * h)
        angular = Rotation.from_matrix(Ta[:3, :3] @ Tb[:3, :3].T).as_rotvec() / (2 * h)
        np.testing.assert_allclose(J[:3, j], linear, rtol=0, atol=1e-7)
        np.testing.assert_allclose(J[3:, j], angular, rtol=0, atol=1e-7)


def test_error_for_known_translation_and_rotation_offset():
    T = _measured_pose()
    offset = np.array([0.01, -0.02, 0.005])
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    angle = 0.3
    R_desired = Rotation.from_rotvec(axis * angle).as_matrix() @ T[:3, :3]  # world-axes turn
    reference = _reference(_pose(R_desired, T[:3, 3] + offset))
    error = CartesianPID().error(T, reference)
    np.testing.assert_allclose(error, np.concatenate([offset, axis * angle]), rtol=0, atol=1e-13)


def test_twist_is_feed_forward_plus_per_axis_proportional_term():
    T = _measured_pose()
    offset = np.array([0.02, 0.01, -0.03])
    axis = np.array([0.0, 0.6, 0.8])
    R_desired = Rotation.from_rotvec(axis * 0.2).as_matrix() @ T[:3, :3]
    feed_forward = np.array([0.1, -0.2, 0.3, 0.4, -0.5, 0.6])
    reference = _reference(_pose(R_desired, T[:3, 3] + offset), feed_forward)
    J = np.random.default_rng(4).normal(size=(6, 7))
    qd = np.ones(7)
    error = np.concatenate([offset, axis * 0.2])
    kp6 = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    pid = CartesianPID(kp=kp6)
    np.testing.assert_allclose(
        pid.twist(T, J, qd, reference, DT), feed_forward + kp6 * error, rtol=0, atol=1e-12
    )
    pair = CartesianPID(kp=(2.0, 7.0))
    expected = feed_forward + np.array([2.0, 2.0, 2.0, 7.0, 7.0, 7.0]) * error
    np.testing.assert_allclose(pair.twist(T, J, qd, reference, DT), expected, rtol=0, atol=1e-12)
    # With no integral gain the integral stays untouched.
    np.testing.assert_array_equal(pair.integral, np.zeros(6))


def test_integral_accumulates_error_times_dt_then_clamps_and_resets():
    T = _measured_pose()
    offset = np.array([0.004, -0.002, 0.001])
    R_desired = Rotation.from_rotvec([0.0, 0.0, 0.01]).as_matrix() @ T[:3, :3]
    reference = _reference(_pose(R_desired, T[:3, 3] + offset))
    error = np.concatenate([offset, [0.0, 0.0, 0.01]])
    limit = np.array([0.01, 0.01, 0.01, 0.05, 0.05, 0.05])
    ki = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    pid = CartesianPID(kp=0.0, ki=ki, integral_limit=(0.01, 0.05))
    J, qd = np.zeros((6, 7)), np.zeros(7)
    dt = 1.0
    for k in range(1, 4):  # 3 steps: 0.012 > 0.01 on the first axis only at the third
        command = pid.twist(T, J, qd, reference, dt)
        expected = np.clip(k * dt * error, -limit, limit)
        np.testing.assert_allclose(pid.integral, expected, rtol=0, atol=1e-15)
        np.testing.assert_allclose(command, ki * expected, rtol=0, atol=1e-14)
    assert pid.integral[0] == pytest.approx(0.01, abs=1e-15)  # clamped (anti-windup)
    for _ in range(1000):
        pid.twist(T, J, qd, reference, dt)
    np.testing.assert_allclose(pid.integral, np.sign(error) * limit, rtol=0, atol=1e-12)
    # The negative side clamps too.
    assert pid.integral[1] == pytest.approx(-0.01, abs=1e-15)  # offset[1] < 0
    copy = pid.integral
    copy[:] = 99.0
    assert np.all(pid.integral <= limit)  # the property returns a copy
    pid.reset()
    np.testing.assert_array_equal(pid.integral, np.zeros(6))
    pid.twist(T, J, qd, reference, dt)
    np.testing.assert_allclose(pid.integral, np.clip(dt * error, -limit, limit), atol=1e-15)


def test_reset_continues_from_a_given_integral():
    T = _measured_pose()
    offset = np.array([0.004, -0.002, 0.001])
    reference = _reference(_pose(T[:3, :3], T[:3, 3] + offset))
    error = np.concatenate([offset, np.zeros(3)])
    pid = CartesianPID(kp=0.0, ki=2.0, integral_limit=(0.01, 0.05))
    start = np.array([0.001, 0.002, -0.003, 0.01, -0.02, 0.03])
    pid.reset(start)
    start[:] = 0.0  # the PID keeps its own copy
    np.testing.assert_array_equal(pid.integral, [0.001, 0.002, -0.003, 0.01, -0.02, 0.03])
    command = pid.twist(T, np.zeros((6, 7)), np.zeros(7), reference, 0.5)
    expected = np.array([0.001, 0.002, -0.003, 0.01, -0.02, 0.03]) + 0.5 * error
    np.testing.assert_allclose(pid.integral, expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(command, 2.0 * expected, rtol=0, atol=1e-14)
    with pytest.raises(InvalidInputError, match="integral"):
        pid.reset([0.0, 0.0])


def test_derivative_term_uses_reference_twist_minus_measured_twist():
    rng = np.random.default_rng(12)
    T = _measured_pose()
    feed_forward = rng.normal(size=6)
    reference = _reference(T.copy(), feed_forward)  # zero pose error
    J = rng.normal(size=(6, 7))
    qd = rng.normal(size=7)
    kd = np.array([0.5, 0.5, 0.5, 0.2, 0.2, 0.2])
    pid = CartesianPID(kp=3.0, kd=(0.5, 0.2))
    expected = feed_forward + kd * (feed_forward - J @ qd)
    np.testing.assert_allclose(pid.twist(T, J, qd, reference, DT), expected, rtol=0, atol=1e-12)


def test_axis_task_ignores_roll_about_tool_axis():
    T = _measured_pose(5)
    R = T[:3, :3]
    z, x = R[:, 2], R[:, 0]
    roll = _pose(R @ Rotation.from_rotvec([0.0, 0.0, 0.4]).as_matrix(), T[:3, 3])
    tilt = _pose(R @ Rotation.from_rotvec([0.3, 0.0, 0.0]).as_matrix(), T[:3, 3])
    pose_pid, axis_pid = CartesianPID(task="pose"), CartesianPID(task="axis")
    # A pure roll is an error of 0.4 rad about the tool z axis, dropped by the axis task.
    np.testing.assert_allclose(pose_pid.error(T, _reference(roll))[3:], 0.4 * z, atol=1e-13)
    np.testing.assert_allclose(axis_pid.error(T, _reference(roll)), np.zeros(6), atol=1e-13)
    # A tilt about the tool x axis is normal to z and is kept whole.
    np.testing.assert_allclose(axis_pid.error(T, _reference(tilt))[3:], 0.3 * x, atol=1e-13)
    np.testing.assert_allclose(
        axis_pid.error(T, _reference(tilt)), pose_pid.error(T, _reference(tilt)), atol=1e-13
    )


def test_axis_task_error_turns_the_tool_axis_onto_the_planned_one_whatever_the_roll():
    rng = np.random.default_rng(21)
    for _ in range(50):
        T = _pose(Rotation.random(random_state=rng).as_matrix(), rng.normal(size=3))
        turn = Rotation.from_rotvec(rng.uniform(-1.0, 1.0, 3)).as_matrix()
        planned = turn @ T[:3, :3]
        reference = _reference(_pose(planned, T[:3, 3] + rng.normal(size=3)))
        full = CartesianPID(task="pose").error(T, reference)
        axis = CartesianPID(task="axis").error(T, reference)
        z, z_d = T[:3, 2], planned[:, 2]
        np.testing.assert_allclose(axis[:3], full[:3], rtol=0, atol=0)
        np.testing.assert_allclose(axis[3:] @ z, 0.0, atol=1e-13)  # normal to the axis
        np.testing.assert_allclose(Rotation.from_rotvec(axis[3:]).apply(z), z_d, atol=1e-12)
        # Rolling the measured tool or the planned one about its own axis changes nothing.
        for roll in (1.0, 2.8, 3.1):
            spin = Rotation.from_rotvec([0.0, 0.0, roll]).as_matrix()
            rolled = _pose(T[:3, :3] @ spin, T[:3, 3])
            again = CartesianPID(task="axis").error(rolled, reference)
            np.testing.assert_allclose(again, axis, atol=1e-12)
            planned_rolled = _reference(_pose(planned @ spin, reference.T_world_tool[:3, 3]))
            np.testing.assert_allclose(
                CartesianPID(task="axis").error(T, planned_rolled), axis, atol=1e-12
            )


def test_unknown_task_raises():
    assert TASKS == ("pose", "axis")
    with pytest.raises(UnknownNameError, match=r"unknown task 'position'; known: pose, axis"):
        CartesianPID(task="position")  # type: ignore[arg-type]
    with pytest.raises(UnknownNameError, match=r"did you mean 'axis'"):
        CartesianPID(task="axes")  # type: ignore[arg-type]


def test_bad_gains_are_refused():
    with pytest.raises(InvalidInputError, match=r"integral_limit must be >= 0"):
        CartesianPID(integral_limit=(-0.01, 0.05))
    with pytest.raises(InvalidInputError, match=r"kd must be a scalar, \[linear, angular\]"):
        CartesianPID(kd=[1.0, 2.0, 3.0])
