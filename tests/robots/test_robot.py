"""Tests of robots.robot: forward kinematics, Jacobians, manipulability, dynamics, pickling."""

from __future__ import annotations

import pickle

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot, race
from scipy.linalg import expm

from optraj.errors import InvalidInputError, UnknownNameError

# ----------------------------------------------------------------- sanity values (robots.md)

SAWYER_NEUTRAL = [0, -1.18, 0, 2.18, 0, 0.57, 3.3161]
YOUBOT_CANDLE = [2.949606, 1.134464, -2.548181, 1.788962, 2.923426]


@pytest.mark.parametrize(
    ("frame", "q", "expected"),
    [
        ("right_hand", np.zeros(7), [1.0155, 0.1603, 0.317]),
        ("right_l6", np.zeros(7), [0.991, 0.1603, 0.317]),
        ("right_hand", SAWYER_NEUTRAL, [0.449598, 0.1603, 0.215754]),
    ],
)
def test_sawyer_sanity_positions(frame, q, expected):
    robot = get_robot("sawyer")
    np.testing.assert_allclose(robot.frame_pose(q, frame)[:3, 3], expected, atol=1e-3)


def test_sawyer_sanity_orientation_at_zero():
    robot = get_robot("sawyer")
    expected = [[0, 0, 1], [-0.98481, -0.17365, 0], [0.17365, -0.98481, 0]]
    np.testing.assert_allclose(
        robot.frame_pose(np.zeros(7), "right_hand")[:3, :3], expected, atol=1e-3
    )


@pytest.mark.parametrize(
    ("joint", "axis", "point"),
    [
        ("right_j0", [0, 0, 1], [0, 0, 0.08]),
        ("right_j1", [0, 1, 0], [0.081, 0.05, 0.317]),
        ("right_j2", [1, 0, 0], [0.221, 0.1925, 0.317]),
        ("right_j3", [0, 1, 0], [0.481, 0.1505, 0.317]),
        ("right_j4", [1, 0, 0], [0.606, 0.024, 0.317]),
        ("right_j5", [0, 1, 0], [0.881, 0.055, 0.317]),
        ("right_j6", [1, 0, 0], [0.991, 0.1603, 0.317]),
    ],
)
def test_sawyer_joint_axes_at_zero(joint, axis, point):
    robot = get_robot("sawyer")
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, np.zeros(7))
    placement = data.oMi[robot.model.getJointId(joint)]
    np.testing.assert_allclose(placement.rotation[:, 2], axis, atol=1e-3)
    np.testing.assert_allclose(placement.translation, point, atol=1e-3)


@pytest.mark.parametrize(
    ("q", "expected"),
    [
        (np.zeros(5), [0.047287, -0.004106, 0.321846]),
        (YOUBOT_CANDLE, [0.054995, 0.000541, 0.535]),
    ],
)
def test_youbot_sanity_positions(q, expected):
    robot = get_robot("youbot")
    np.testing.assert_allclose(robot.frame_pose(q, "arm_link_5")[:3, 3], expected, atol=1e-3)


@pytest.mark.parametrize(
    ("joint", "height"),
    [("arm_joint_2", 0.115), ("arm_joint_3", 0.270), ("arm_joint_4", 0.405)],
)
def test_youbot_candle_joint_heights(joint, height):
    robot = get_robot("youbot")
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, np.array(YOUBOT_CANDLE))
    assert data.oMi[robot.model.getJointId(joint)].translation[2] == pytest.approx(height, abs=1e-3)


def test_youbot_candle_joint2_axis_point():
    robot = get_robot("youbot")
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, np.array(YOUBOT_CANDLE))
    np.testing.assert_allclose(
        data.oMi[robot.model.getJointId("arm_joint_2")].translation[:2],
        [0.056995, 0.000576],
        atol=1e-3,
    )


def test_youbot_tcp_is_0875_along_link5_z():
    robot = get_robot("youbot")
    q = np.array(YOUBOT_CANDLE)
    link5 = robot.frame_pose(q, "arm_link_5")
    np.testing.assert_allclose(
        robot.tool_pose(q)[:3, 3], link5[:3, 3] + 0.0875 * link5[:3, 2], atol=1e-12
    )


# ------------------------------------------------------- paddle4 against its PoE description


def _twist_matrix(twist):
    w, v = np.asarray(twist[:3], float), np.asarray(twist[3:], float)
    out = np.zeros((4, 4))
    out[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    out[:3, 3] = v
    return out


PADDLE_S = [[0, 0, 0, 0, 0, 1], [0, 0, 1, 0, 0.9, 0], [0, 0, 0, 1, 0, 0], [0, 0, 1, 0, -0.2, 0]]
PADDLE_M = np.array([[0, 0, 1, 0.25], [1, 0, 0, 0], [0, 1, 0, -0.2], [0, 0, 0, 1]], float)


def test_paddle4_matches_product_of_exponentials():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(3)
    for q in robot.random_configurations(100, rng):
        expected = np.eye(4)
        for twist, value in zip(PADDLE_S, q, strict=True):
            expected = expected @ expm(_twist_matrix(twist) * value)
        expected = expected @ PADDLE_M
        np.testing.assert_allclose(robot.tool_pose(q), expected, atol=1e-12)


def test_paddle4_home_is_seed_home_pose():
    robot = get_robot("paddle4")
    expected = np.array([[0, 0, 1, 0.25], [1, 0, 0, 0], [0, 1, 0, 0.25], [0, 0, 0, 1]], float)
    np.testing.assert_allclose(robot.tool_pose(robot.home), expected, atol=1e-12)


def test_sawyer_cue_tip_lies_on_flange_z_axis():
    from optraj import robots

    robot = robots.load("sawyer", cue_length=0.45)
    q = np.array(SAWYER_NEUTRAL)
    hand = robot.frame_pose(q, "right_hand")
    tip = robot.tool_pose(q)
    np.testing.assert_allclose(tip[:3, 3], hand[:3, 3] + 0.45 * hand[:3, 2], atol=1e-12)
    np.testing.assert_allclose(tip[:3, :3], hand[:3, :3], atol=1e-12)


# ----------------------------------------------------------------- Jacobian and vectorising


def test_jacobian_matches_finite_differences(any_robot):
    robot = any_robot
    rng = np.random.default_rng(5)
    h = 1e-6
    for q in robot.random_configurations(10, rng):
        jac = robot.jacobian(q)
        T = robot.tool_pose(q)
        for j in range(robot.dof):
            dq = np.zeros(robot.dof)
            dq[j] = h
            T_plus, T_minus = robot.tool_pose(q + dq), robot.tool_pose(q - dq)
            np.testing.assert_allclose(
                jac[:3, j], (T_plus[:3, 3] - T_minus[:3, 3]) / (2 * h), atol=1e-7
            )
            # Angular velocity from dR/dt R^T (world axes).
            omega_hat = (T_plus[:3, :3] - T_minus[:3, :3]) / (2 * h) @ T[:3, :3].T
            omega = [omega_hat[2, 1], omega_hat[0, 2], omega_hat[1, 0]]
            np.testing.assert_allclose(jac[3:, j], omega, atol=1e-7)


def test_vectorised_kinematics_equal_single_calls(any_robot):
    robot = any_robot
    qs = robot.random_configurations(6, np.random.default_rng(8))
    poses, jacs = robot.tool_pose(qs), robot.jacobian(qs)
    assert poses.shape == (6, 4, 4)
    assert jacs.shape == (6, 6, robot.dof)
    for k, q in enumerate(qs):
        np.testing.assert_array_equal(poses[k], robot.tool_pose(q))
        np.testing.assert_array_equal(jacs[k], robot.jacobian(q))
    np.testing.assert_array_equal(robot.tool_position(qs), poses[:, :3, 3])


def test_manipulability_is_sqrt_det_for_translation(any_robot):
    robot = any_robot
    for q in robot.random_configurations(5, np.random.default_rng(2)):
        jv = robot.jacobian(q)[:3]
        expected = np.sqrt(np.linalg.det(jv @ jv.T))
        assert robot.manipulability(q, part="translation") == pytest.approx(
            expected, rel=1e-9, abs=1e-15
        )


def test_manipulability_vanishes_at_youbot_candle_singularity():
    # Arm straight up: J2-J4 stretched in line and the J1 and J5 axes both vertical.
    robot = get_robot("youbot")
    bent = np.add(YOUBOT_CANDLE, [0.0, 0.3, -0.6, 0.3, 0.0])
    assert robot.manipulability(YOUBOT_CANDLE) < 1e-9
    assert robot.manipulability(bent) > 1e-4


def test_manipulability_rejects_unknown_part():
    robot = get_robot("sawyer")
    with pytest.raises(UnknownNameError, match="translation"):
        robot.manipulability(robot.home, part="linear")


# ------------------------------------------------------------------------------ dynamics


def test_inverse_dynamics_matches_pinocchio_and_gravity(any_robot):
    robot = any_robot
    rng = np.random.default_rng(4)
    qs = robot.random_configurations(4, rng)
    vs, accs = rng.uniform(-1, 1, qs.shape), rng.uniform(-1, 1, qs.shape)
    tau = robot.inverse_dynamics(qs, vs, accs)
    data = robot.model.createData()
    for k in range(4):
        np.testing.assert_allclose(
            tau[k], pin.rnea(robot.model, data, qs[k], vs[k], accs[k]), atol=1e-12
        )
        zero = np.zeros(robot.dof)
        np.testing.assert_allclose(
            robot.gravity_torque(qs[k]), robot.inverse_dynamics(qs[k], zero, zero), atol=1e-12
        )


def test_paddle4_lift_force_is_weight_of_moving_parts():
    robot = get_robot("paddle4")
    # Chosen masses in paddle4.urdf: 4.0 + 2.0 + 1.5 + 0.25 kg ride on J1.
    assert robot.gravity_torque(robot.home)[0] == pytest.approx(7.75 * 9.81, rel=1e-9)


def test_inverse_dynamics_rejects_mismatched_shapes():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match="same shape"):
        robot.inverse_dynamics(np.zeros((2, 4)), np.zeros((3, 4)), np.zeros((2, 4)))


# ------------------------------------------------------------------------- input checking


@pytest.mark.parametrize(
    ("q", "match"),
    [
        (np.zeros(3), r"shape \(4,\)"),
        (np.zeros((2, 5)), r"shape \(any, 4\)"),
        ([0.1, np.nan, 0, 0], "finite"),
        ("abc", "numeric"),
    ],
)
def test_kinematics_reject_bad_configurations(q, match):
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match=match):
        robot.tool_pose(q)


def test_unknown_frame_lists_frames():
    robot = get_robot("youbot")
    with pytest.raises(UnknownNameError, match="tcp") as info:
        robot.frame_pose(robot.home, "gripper")
    assert "arm_link_5" in info.value.known


def test_robot_pickles_and_keeps_working(any_robot):
    robot = any_robot
    q = robot.random_configurations(1, np.random.default_rng(0))[0]
    clone = pickle.loads(pickle.dumps(robot))
    np.testing.assert_array_equal(clone.tool_pose(q), robot.tool_pose(q))
    assert clone.limits.names == robot.limits.names
    np.testing.assert_array_equal(clone.home, robot.home)


def test_non_string_frame_and_part_raise_typed_errors():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match="frame must be a frame name"):
        robot.frame_pose(robot.home, 3)
    with pytest.raises(UnknownNameError, match="translation"):
        robot.manipulability(robot.home, part=["full"])


def test_overflowing_dynamics_raise_instead_of_returning_nan():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match="non-finite"):
        robot.inverse_dynamics(robot.home, [0.0, 1e160, 0.0, 0.0], np.zeros(4))


def test_kinematics_are_thread_safe():
    robot = get_robot("sawyer")
    qs = robot.random_configurations(400, np.random.default_rng(21))
    expected = robot.tool_pose(qs)

    def work(offset: int) -> None:
        for k in range(offset, offset + 400, 7):
            i = k % 400
            np.testing.assert_array_equal(robot.tool_pose(qs[i]), expected[i])

    assert race(work, 8) == []


def test_fingerprint_tells_models_apart_not_names():
    from optraj import robots

    default, again = robots.load("sawyer"), robots.load("sawyer")
    assert (
        default.fingerprint == again.fingerprint == pickle.loads(pickle.dumps(default)).fingerprint
    )
    assert len(default.fingerprint) == 64
    # Same name, other links or tool: another model.
    for other in (robots.load("sawyer", cue_length=0.45), robots.load("sawyer", cue_mass=0.2)):
        assert other.name == default.name and other.fingerprint != default.fingerprint
    assert robots.load("paddle4").fingerprint != default.fingerprint
