from __future__ import annotations

import pickle

import numpy as np
import pytest
from conftest import get_robot
from scipy.spatial.transform import Rotation

from optraj.controllers.controller import Command, Reference, State
from optraj.controllers.pseudo_inverse_pid import PseudoInversePID
from optraj.errors import InvalidInputError, UnknownNameError

DT = 1e-3


def _inner_configurations(robot, count, rng):
    """Configurations in the middle 60 % of each joint range (away from the extremes)."""
    limits = robot.limits
    middle = (limits.lower + limits.upper) / 2
    half = (limits.upper - limits.lower) / 2
    return middle + rng.uniform(-0.6, 0.6, (count, robot.dof)) * half


def _reference(T_desired, twist, n):
    zeros = np.zeros(n)
    return Reference(0.0, zeros, zeros, zeros, T_desired, np.asarray(twist, dtype=float), "")


def _state(q):
    return State(0.0, q, np.zeros_like(q))


def _minimum_norm(robot, q, twist):
    """The smallest joint velocity whose tool twist is nearest ``twist`` (least squares)."""
    return np.linalg.lstsq(robot.jacobian(q), twist, rcond=None)[0]


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_step_is_minimum_norm_least_squares_of_twist(name):
    robot = get_robot(name)
    rng = np.random.default_rng(31)
    controller = PseudoInversePID(robot, kp=20.0, ki=0.0, kd=0.0)
    for q in _inner_configurations(robot, 10, rng):
        twist = rng.normal(size=6)
        reference = _reference(robot.tool_pose(q), twist, robot.dof)
        command = controller.step(_state(q), reference, DT)
        assert isinstance(command, Command)
        assert command.status == "ok"
        assert not command.fallback
        np.testing.assert_allclose(command.qd, _minimum_norm(robot, q, twist), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_step_includes_proportional_term(name):
    robot = get_robot(name)
    rng = np.random.default_rng(32)
    controller = PseudoInversePID(robot, kp=(4.0, 9.0), ki=0.0, kd=0.0)
    for q in _inner_configurations(robot, 5, rng):
        T = robot.tool_pose(q)
        offset = rng.uniform(-0.01, 0.01, 3)
        turn = rng.uniform(-0.05, 0.05, 3)
        T_desired = T.copy()
        T_desired[:3, 3] += offset
        T_desired[:3, :3] = Rotation.from_rotvec(turn).as_matrix() @ T[:3, :3]
        twist = rng.normal(size=6)
        command = controller.step(_state(q), _reference(T_desired, twist, robot.dof), DT)
        v = twist + np.concatenate([4.0 * offset, 9.0 * turn])
        np.testing.assert_allclose(command.qd, _minimum_norm(robot, q, v), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_damped_step_equals_svd_formula(name):
    robot = get_robot(name)
    rng = np.random.default_rng(33)
    damping = 0.05
    controller = PseudoInversePID(robot, ki=0.0, damping=damping)
    for q in [*_inner_configurations(robot, 6, rng), robot.home]:
        twist = rng.normal(size=6)
        command = controller.step(_state(q), _reference(robot.tool_pose(q), twist, robot.dof), DT)
        U, s, Vt = np.linalg.svd(robot.jacobian(q), full_matrices=False)
        expected = Vt.T @ ((s / (s**2 + damping**2)) * (U.T @ twist))
        np.testing.assert_allclose(command.qd, expected, rtol=1e-9, atol=1e-10)
        # Damping shrinks the command compared with the plain pseudo-inverse.
        plain = _minimum_norm(robot, q, twist)
        assert np.linalg.norm(command.qd) < np.linalg.norm(plain)


def _axis_task_steps(seed, count):
    """Sawyer's axis-task steps from random inner configurations: (robot, q, T, twist, command)."""
    robot = get_robot("sawyer")
    rng = np.random.default_rng(seed)
    controller = PseudoInversePID(robot, ki=0.0, task="axis")
    for q in _inner_configurations(robot, count, rng):
        T = robot.tool_pose(q)
        twist = rng.normal(size=6)
        yield robot, q, T, twist, controller.step(_state(q), _reference(T, twist, robot.dof), DT)


def test_axis_task_reproduces_twist_except_about_tool_axis():
    for robot, q, T, twist, command in _axis_task_steps(34, 10):
        z = T[:3, 2]
        achieved = robot.jacobian(q) @ command.qd
        np.testing.assert_allclose(achieved[:3], twist[:3], rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            achieved[3:] - (achieved[3:] @ z) * z, twist[3:] - (twist[3:] @ z) * z, atol=1e-9
        )
        # Freeing the roll gives a smaller joint velocity than the full 6-D task.
        full = _minimum_norm(robot, q, twist)
        assert np.linalg.norm(command.qd) <= np.linalg.norm(full) + 1e-12


def test_axis_task_is_minimum_norm_solution_of_five_rows():
    for robot, q, T, twist, command in _axis_task_steps(35, 5):
        # Independent basis of the plane normal to z: the tool x and y axes.
        basis = T[:3, :2].T
        J = robot.jacobian(q)
        A = np.vstack([J[:3], basis @ J[3:]])
        b = np.concatenate([twist[:3], basis @ twist[3:]])
        expected = np.linalg.lstsq(A, b, rcond=None)[0]
        np.testing.assert_allclose(command.qd, expected, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_proportional_step_reduces_pose_error(name):
    robot = get_robot(name)
    rng = np.random.default_rng(36)
    kp, dt = 20.0, 1e-3
    controller = PseudoInversePID(robot, kp=kp, ki=0.0)
    for q in _inner_configurations(robot, 5, rng):
        q_ref = q + rng.normal(0.0, 1e-3, robot.dof)
        T_ref = robot.tool_pose(q_ref)
        reference = _reference(T_ref, np.zeros(6), robot.dof)

        def pose_error(qk, T_ref=T_ref):
            T = robot.tool_pose(qk)
            turn = Rotation.from_matrix(T_ref[:3, :3] @ T[:3, :3].T).as_rotvec()
            return np.concatenate([T_ref[:3, 3] - T[:3, 3], turn])

        before = np.linalg.norm(pose_error(q))
        qd = controller.step(_state(q), reference, dt).qd
        after = np.linalg.norm(pose_error(q + qd * dt))
        assert after < before
        if robot.dof >= 6:  # J J^+ = I: the error shrinks by (1 - kp dt) to first order
            assert after / before == pytest.approx(1.0 - kp * dt, abs=2e-3)


def test_reset_clears_integral():
    robot = get_robot("sawyer")
    q = robot.home
    T_ref = robot.tool_pose(q)
    T_ref[:3, 3] += [0.002, 0.0, -0.001]
    reference = _reference(T_ref, np.zeros(6), robot.dof)
    controller = PseudoInversePID(robot, kp=1.0, ki=5.0)
    first = controller.step(_state(q), reference, 0.01).qd
    assert np.any(controller.pid.integral != 0.0)
    np.testing.assert_allclose(controller.pid.integral[:3], [2e-5, 0.0, -1e-5], atol=1e-15)
    second = controller.step(_state(q), reference, 0.01).qd
    assert not np.allclose(first, second, rtol=0, atol=1e-12)  # the integral acts
    controller.reset(_state(q))
    np.testing.assert_array_equal(controller.pid.integral, np.zeros(6))
    np.testing.assert_allclose(
        controller.step(_state(q), reference, 0.01).qd, first, rtol=0, atol=1e-15
    )


def test_controller_pickles_with_its_integral():
    robot = get_robot("paddle4")
    controller = PseudoInversePID(robot, ki=2.0, damping=0.01)
    T_ref = robot.tool_pose(robot.home)
    T_ref[:3, 3] += 0.003
    reference = _reference(T_ref, np.zeros(6), robot.dof)
    controller.step(_state(robot.home), reference, 0.01)
    clone = pickle.loads(pickle.dumps(controller))
    np.testing.assert_array_equal(clone.pid.integral, controller.pid.integral)
    np.testing.assert_allclose(
        clone.step(_state(robot.home), reference, 0.01).qd,
        controller.step(_state(robot.home), reference, 0.01).qd,
        rtol=0,
        atol=1e-15,
    )


def test_name_depends_on_damping():
    robot = get_robot("paddle4")
    assert PseudoInversePID(robot).name == "pseudo-inverse PID"
    assert PseudoInversePID(robot, damping=0.1).name == "damped pseudo-inverse PID"


def test_bad_arguments_raise():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match=r"damping must be >= 0, got -0.1"):
        PseudoInversePID(robot, damping=-0.1)
    with pytest.raises(InvalidInputError, match=r"damping must be finite"):
        PseudoInversePID(robot, damping=float("nan"))
    with pytest.raises(InvalidInputError, match=r"damping must have shape \(\)"):
        PseudoInversePID(robot, damping=[0.1, 0.2])  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"kp must be >= 0"):
        PseudoInversePID(robot, kp=-1.0)
    with pytest.raises(UnknownNameError, match=r"unknown task 'roll'"):
        PseudoInversePID(robot, task="roll")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"feedforward must be True or False, got 1"):
        PseudoInversePID(robot, feedforward=1)  # type: ignore[arg-type]


@pytest.mark.parametrize("task", ["pose", "axis"])
def test_the_command_carries_the_plans_feed_forward_torque(task):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(33)
    q = _inner_configurations(robot, 1, rng)[0]
    tau = rng.normal(0.0, 5.0, robot.dof)
    reference = _reference(robot.tool_pose(q), rng.normal(size=6), robot.dof)._replace(tau=tau)
    with_torque = PseudoInversePID(robot, task=task).step(_state(q), reference, DT)
    without = PseudoInversePID(robot, task=task, feedforward=False).step(_state(q), reference, DT)
    np.testing.assert_array_equal(with_torque.tau, tau)
    assert without.tau is None
    np.testing.assert_array_equal(with_torque.qd, without.qd)  # the velocity is the same
    unknown = PseudoInversePID(robot, task=task).step(_state(q), reference._replace(tau=None), DT)
    assert unknown.tau is None


@pytest.mark.parametrize(
    ("damping", "match"),
    [
        (9.7e-107, r"damping must be 0 \(the plain pseudo-inverse\) or >= 1e-06, got 9\.7e-107"),
        (1e308, r"damping must be <= 1000, got 1e\+308"),
    ],
)
def test_a_damping_lost_in_round_off_or_overflowing_is_refused(damping, match):
    # 9.7e-107 made the inverse of a rank-deficient axis task singular (a numpy LinAlgError
    # at the first step), 1e308 overflowed lambda^2.
    with pytest.raises(InvalidInputError, match=match):
        PseudoInversePID(get_robot("paddle4"), task="axis", damping=damping)


def test_a_robot_that_is_not_a_robot_or_a_string_damping_is_refused():
    with pytest.raises(InvalidInputError, match=r"robot must be a robots\.Robot"):
        PseudoInversePID(None)  # refused when built, not at the first step
    with pytest.raises(InvalidInputError, match="damping must be a numeric"):
        PseudoInversePID(get_robot("sawyer"), damping="0.1")
