from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot
from scipy.spatial.transform import Rotation

from optraj.controllers.controller import (
    Command,
    Controller,
    Reference,
    References,
    State,
    as_gains,
    cross3,
    rotation_error,
    sample_references,
)
from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Phase, Trajectory

SAWYER_STEP = np.array([0.25, -0.2, 0.3, 0.15, -0.3, 0.2, 0.4])
PADDLE_STEP = np.array([0.2, 0.5, 0.3, -0.4])
PAIR = ("linear", "angular")


def _smooth_trajectory(robot, step, phases=()):
    """A quintic joint motion home -> home + step -> home + step / 2 over 2 s."""
    q0 = robot.home
    q = np.stack([q0, q0 + step, q0 + 0.5 * step])
    qd = np.stack([np.zeros(robot.dof), 0.3 * step, np.zeros(robot.dof)])
    qdd = np.zeros_like(q)
    return Trajectory.from_hermite([0.0, 1.0, 2.0], q, qd, qdd, phases=phases)


@pytest.mark.parametrize(("name", "step"), [("sawyer", SAWYER_STEP), ("paddle4", PADDLE_STEP)])
def test_sample_references_matches_robot_kinematics(name, step):
    robot = get_robot(name)
    traj = _smooth_trajectory(robot, step)
    t = np.linspace(0.0, traj.duration, 23)
    refs = sample_references(robot, traj, t)
    sample = traj.sample(t)
    assert len(refs) == t.size
    np.testing.assert_allclose(refs.t, t, rtol=0, atol=0)
    np.testing.assert_allclose(refs.q, sample.q, rtol=0, atol=1e-15)
    np.testing.assert_allclose(refs.qd, sample.qd, rtol=0, atol=1e-15)
    np.testing.assert_allclose(refs.qdd, sample.qdd, rtol=0, atol=1e-15)
    for k in range(t.size):
        np.testing.assert_allclose(
            refs.T_world_tool[k], robot.tool_pose(sample.q[k]), rtol=0, atol=1e-12
        )
        np.testing.assert_allclose(
            refs.twist[k], robot.jacobian(sample.q[k]) @ sample.qd[k], rtol=0, atol=1e-12
        )
    assert refs.phase == ("",) * t.size


@pytest.mark.parametrize(("name", "step"), [("sawyer", SAWYER_STEP), ("paddle4", PADDLE_STEP)])
def test_feed_forward_torque_is_the_inverse_dynamics_without_gravity(name, step):
    # Independent reference: M(q) qdd + C(q, qd) qd from Pinocchio's CRBA and Coriolis
    # matrix (not RNEA), at seeded random times of the plan.
    robot = get_robot(name)
    traj = _smooth_trajectory(robot, 2.0 * step)
    rng = np.random.default_rng(27)
    t = np.sort(rng.uniform(0.0, traj.duration, 40))
    refs = sample_references(robot, traj, t)
    data = robot.model.createData()
    expected = np.empty((t.size, robot.dof))
    for k in range(t.size):
        q, qd, qdd = refs.q[k], refs.qd[k], refs.qdd[k]
        upper = pin.crba(robot.model, data, q)
        M = np.triu(upper) + np.triu(upper, 1).T
        C = pin.computeCoriolisMatrix(robot.model, data, q, qd)
        expected[k] = M @ qdd + C @ qd
    assert refs.tau.shape == (t.size, robot.dof)
    scale = np.abs(expected).max()
    assert scale > 0.1  # the plan moves the arm: the check is not vacuous
    np.testing.assert_allclose(refs.tau, expected, rtol=0, atol=1e-10 * scale)
    # And it is the robot's inverse dynamics less its gravity torque.
    np.testing.assert_allclose(
        refs.tau,
        robot.inverse_dynamics(refs.q, refs.qd, refs.qdd) - robot.gravity_torque(refs.q),
        rtol=0,
        atol=1e-12 * scale,
    )


def test_feed_forward_torque_is_zero_at_rest_and_optional():
    robot = get_robot("sawyer")
    q = np.stack([robot.home, robot.home])
    still = Trajectory.from_hermite([0.0, 1.0], q, np.zeros_like(q), np.zeros_like(q))
    refs = sample_references(robot, still, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(refs.tau, 0.0, rtol=0, atol=1e-12)
    assert np.abs(robot.gravity_torque(robot.home)).max() > 1.0  # gravity is taken out
    without = References(
        refs.t, refs.q, refs.qd, refs.qdd, refs.T_world_tool, refs.twist, refs.phase
    )
    assert without.tau is None
    assert without[1].tau is None


@pytest.mark.parametrize(("name", "step"), [("sawyer", SAWYER_STEP), ("paddle4", PADDLE_STEP)])
def test_twist_matches_finite_difference_of_tool_pose(name, step):
    robot = get_robot(name)
    traj = _smooth_trajectory(robot, step)
    h = 1e-5
    t = np.array([0.137, 0.41, 0.77, 1.23, 1.58, 1.9])
    refs = sample_references(robot, traj, t)
    before = robot.tool_pose(traj.sample(t - h).q)
    after = robot.tool_pose(traj.sample(t + h).q)
    linear = (after[:, :3, 3] - before[:, :3, 3]) / (2 * h)
    # Angular velocity in world axes: R(t + h) = exp(2 h [w]) R(t - h).
    angular = np.array(
        [
            Rotation.from_matrix(Ra[:3, :3] @ Rb[:3, :3].T).as_rotvec() / (2 * h)
            for Ra, Rb in zip(after, before, strict=True)
        ]
    )
    assert np.linalg.norm(refs.twist, axis=1).min() > 1e-2  # the check is not vacuous
    np.testing.assert_allclose(refs.twist[:, :3], linear, rtol=0, atol=1e-7)
    np.testing.assert_allclose(refs.twist[:, 3:], angular, rtol=0, atol=1e-7)


def test_phase_labels_inside_outside_and_at_shared_boundaries():
    robot = get_robot("paddle4")
    phases = [Phase("approach", 0.0, 0.8), Phase("strike", 0.8, 1.4)]
    traj = _smooth_trajectory(robot, PADDLE_STEP, phases)
    t = np.array([0.0, 0.5, 0.8, 1.0, 1.4, 1.41, 2.0])
    refs = sample_references(robot, traj, t)
    # The later phase wins at the shared boundary 0.8 s; 1.4 s is the strike's closed end.
    assert refs.phase == ("approach", "approach", "strike", "strike", "strike", "", "")
    assert [refs[k].phase for k in range(len(refs))] == list(refs.phase)


def test_references_getitem_and_len():
    robot = get_robot("sawyer")
    traj = _smooth_trajectory(robot, SAWYER_STEP, [Phase("strike", 0.5, 1.5)])
    t = np.linspace(0.0, 2.0, 9)
    refs = sample_references(robot, traj, t)
    assert isinstance(refs, References)
    assert len(refs) == 9
    for k in (0, 3, 8, -1):
        ref = refs[k]
        assert isinstance(ref, Reference)
        assert isinstance(ref.t, float)
        assert ref.t == pytest.approx(t[k], abs=0)
        np.testing.assert_array_equal(ref.q, refs.q[k])
        np.testing.assert_array_equal(ref.qd, refs.qd[k])
        np.testing.assert_array_equal(ref.qdd, refs.qdd[k])
        np.testing.assert_array_equal(ref.T_world_tool, refs.T_world_tool[k])
        np.testing.assert_array_equal(ref.twist, refs.twist[k])
        np.testing.assert_array_equal(ref.tau, refs.tau[k])
        assert ref.phase == refs.phase[k]
    assert refs[4].phase == "strike"
    assert refs[0].phase == ""
    with pytest.raises(IndexError):
        refs[9]


def test_command_fallback_and_defaults():
    qd = np.array([0.1, -0.2])
    command = Command(qd)
    assert command.status == "ok"
    assert command.fallback is False
    assert command.tau is None
    held = Command(np.zeros(2), "fallback: solver failed")
    assert held.fallback is True
    assert held.tau is None
    pushed = Command(qd, "ok", np.array([1.5, -2.0]))
    assert pushed.qd is qd and pushed.status == "ok"
    np.testing.assert_array_equal(pushed.tau, [1.5, -2.0])
    assert Command._fields == ("qd", "status", "tau")
    assert Reference(0.0, qd, qd, qd, np.eye(4), np.zeros(6)).phase == ""
    assert Reference(0.0, qd, qd, qd, np.eye(4), np.zeros(6), "strike").tau is None
    assert Reference._fields[-2:] == ("phase", "tau")
    state = State(0.5, qd, qd)
    assert state.t == 0.5


def test_controller_base_is_abstract_and_names_by_class():
    with pytest.raises(TypeError):
        Controller()  # type: ignore[abstract]

    class Hold(Controller):
        def reset(self, state):
            pass

        def step(self, state, reference, dt):
            return Command(np.zeros_like(state.q))

    assert Hold().name == "Hold"


def _rotation(axis, angle):
    axis = np.asarray(axis, dtype=float)
    return Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()


def test_cross3_matches_numpy_cross():
    rng = np.random.default_rng(21)
    for _ in range(200):
        a, b = rng.normal(size=3) * rng.uniform(1e-3, 1e3), rng.normal(size=3)
        np.testing.assert_allclose(
            cross3(a, b), np.cross(a, b), rtol=1e-14, atol=1e-14 * abs(a).max()
        )
    matrix = rng.normal(size=(3, 3))  # column views, as the controllers pass them
    np.testing.assert_allclose(
        cross3(matrix[:, 0], matrix[:, 2]), np.cross(matrix[:, 0], matrix[:, 2])
    )


def test_rotation_error_hand_computed():
    R = _rotation([0.3, -1.0, 0.5], 0.7)
    R_desired = _rotation([0.0, 0.0, 1.0], 0.4) @ R  # a 0.4 rad turn about world z
    np.testing.assert_allclose(rotation_error(R_desired, R), [0.0, 0.0, 0.4], rtol=0, atol=1e-14)
    np.testing.assert_allclose(rotation_error(R, R), np.zeros(3), rtol=0, atol=1e-15)
    # Turning R_desired back into R is the opposite rotation.
    np.testing.assert_allclose(rotation_error(R, R_desired), [0.0, 0.0, -0.4], rtol=0, atol=1e-14)


def test_rotation_error_at_pi_has_the_right_angle_and_rotation():
    R = _rotation([1.0, 2.0, -0.5], 1.1)
    axis = np.array([2.0, -1.0, 2.0]) / 3.0
    R_desired = _rotation(axis, np.pi) @ R
    e = rotation_error(R_desired, R)
    assert np.linalg.norm(e) == pytest.approx(np.pi, abs=1e-9)
    # At pi the sign of the axis is free; either must reproduce the rotation.
    assert min(np.linalg.norm(e - np.pi * axis), np.linalg.norm(e + np.pi * axis)) < 1e-7
    np.testing.assert_allclose(
        Rotation.from_rotvec(e).as_matrix() @ R, R_desired, rtol=0, atol=1e-9
    )


def test_rotation_error_random_stress_against_scipy():
    rng = np.random.default_rng(20240611)
    near_pi = np.pi - np.array([0.0, 1e-12, 1e-9, 1e-6, 1e-4, 1e-2])
    small = np.array([0.0, 1e-12, 1e-8, 1e-4])
    angles = np.concatenate([rng.uniform(0.0, np.pi, 400), near_pi, small])
    for angle in angles:
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        R = Rotation.random(random_state=rng).as_matrix()
        R_desired = Rotation.from_rotvec(axis * angle).as_matrix() @ R
        e = rotation_error(R_desired, R)
        assert e.shape == (3,)
        assert np.linalg.norm(e) == pytest.approx(angle, abs=1e-7)
        reference = Rotation.from_matrix(R_desired @ R.T).as_rotvec()
        if angle < np.pi - 1e-3:
            np.testing.assert_allclose(e, reference, rtol=0, atol=1e-7)
            np.testing.assert_allclose(e, axis * angle, rtol=0, atol=1e-7)
        else:  # the axis sign may flip as the angle reaches pi
            gap = min(np.linalg.norm(e - axis * angle), np.linalg.norm(e + axis * angle))
            assert gap < 1e-6, (angle, e, axis)
        np.testing.assert_allclose(
            Rotation.from_rotvec(e).as_matrix() @ R, R_desired, rtol=0, atol=1e-9
        )


def test_sample_references_rejects_wrong_dof_trajectory():
    sawyer = get_robot("sawyer")
    paddle_traj = _smooth_trajectory(get_robot("paddle4"), PADDLE_STEP)
    with pytest.raises(InvalidInputError, match=r"trajectory has 4 joints, robot 'sawyer' has 7"):
        sample_references(sawyer, paddle_traj, [0.0, 1.0])


def test_sample_references_rejects_non_trajectory():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match=r"must be a planners\.Trajectory, got dict"):
        sample_references(robot, {"q": robot.home}, [0.0])  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", [[-0.01, 0.5], [0.0, 2.001], [0.0, 5.0]])
def test_sample_references_rejects_times_outside(bad):
    robot = get_robot("paddle4")
    traj = _smooth_trajectory(robot, PADDLE_STEP)
    with pytest.raises(InvalidInputError, match=r"outside the trajectory \[0, 2\] s"):
        sample_references(robot, traj, bad)


def test_sample_references_rejects_non_finite_and_non_vector_times():
    robot = get_robot("paddle4")
    traj = _smooth_trajectory(robot, PADDLE_STEP)
    with pytest.raises(InvalidInputError, match=r"times must be finite"):
        sample_references(robot, traj, [0.0, np.nan])
    with pytest.raises(InvalidInputError, match=r"times must have shape"):
        sample_references(robot, traj, [[0.0, 1.0]])


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (2.5, np.full(6, 2.5)),
        (np.float64(1.0), np.ones(6)),
        ([1.0, 3.0], [1.0, 1.0, 1.0, 3.0, 3.0, 3.0]),
        ([1, 2, 3, 4, 5, 6], [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
        ([0.0], np.zeros(6)),
    ],
)
def test_as_gains_shapes(value, expected):
    gains = as_gains(value, "kp", 6, unit="[1/s]", halves=PAIR)
    assert gains.shape == (6,)
    assert gains.dtype == np.float64
    np.testing.assert_allclose(gains, expected, rtol=0, atol=0)


def test_as_gains_errors():
    with pytest.raises(InvalidInputError, match=r"kp must be >= 0 \[1/s\]"):
        as_gains(-1.0, "kp", 6, unit="[1/s]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"ki must be >= 0"):
        as_gains([1.0, -0.1], "ki", 6, unit="[1/s^2]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"scalar, \[linear, angular\] or 6 values, got 3"):
        as_gains([1.0, 2.0, 3.0], "kd", 6, unit="[-]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"got 7 values"):
        as_gains(np.ones(7), "kd", 6, unit="[-]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"kp must be finite"):
        as_gains(np.nan, "kp", 6, unit="[1/s]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"kp must have shape"):
        as_gains(np.ones((2, 3)), "kp", 6, unit="[1/s]", halves=PAIR)
    with pytest.raises(InvalidInputError, match=r"one gain per joint \(4\), got 3"):
        as_gains([1.0, 2.0, 3.0], "kp", 4)
