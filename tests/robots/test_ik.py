"""Tests of robots.ik: numerical IK for every robot, judged by forward kinematics."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ALL_ROBOTS, get_robot

from optraj.errors import InvalidInputError, UnknownNameError, UnreachableError
from optraj.robots import ik as ik_module
from optraj.robots import solve_ik
from optraj.robots.ik import LocalIK


@pytest.mark.parametrize("name", ALL_ROBOTS)
@pytest.mark.parametrize(
    ("target_of", "count", "seed"),
    [pytest.param("tool_pose", 1000, 1000, marks=pytest.mark.slow), ("tool_position", 200, 77)],
)
def test_round_trip_of_random_poses_and_positions(name, target_of, count, seed):
    # The tool pose (full pose IK) or its position (position-only IK) of random configurations.
    robot = get_robot(name)
    target_of = getattr(robot, target_of)
    for q_true in robot.random_configurations(count, np.random.default_rng(seed)):
        target = target_of(q_true)
        solution = solve_ik(robot, target)
        np.testing.assert_allclose(target_of(solution.q), target, atol=1e-6)
        assert robot.limits.contains(solution.q)
        if target.shape == (3,):
            assert solution.orientation_error == 0.0


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_unreachable_target_raises_typed_error(name):
    robot = get_robot(name)
    far = robot.tool_position(robot.home) + np.array([5.0, 0.0, 0.0])
    with pytest.raises(UnreachableError, match="no configuration") as info:
        solve_ik(robot, far, restarts=5)
    assert info.value.position_error > 3.0
    assert info.value.attempts == 6


def test_pose_needing_a_joint_beyond_its_limit_is_unreachable():
    # paddle4's normal can turn at most 90 deg from the arm: a paddle facing back toward the
    # base (normal = -x) with the arm pointing +x needs J4 = pi, beyond its limit.
    robot = get_robot("paddle4")
    target = robot.tool_pose(robot.home)
    target[:3, :3] = target[:3, :3] @ np.diag([-1.0, 1.0, -1.0])  # turn 180 deg about tool y
    with pytest.raises(UnreachableError):
        solve_ik(robot, target, restarts=10)


def test_returns_solution_near_q_near_for_youbot():
    # A 5-DOF arm has isolated pose solutions: starting next to one returns exactly it.
    robot = get_robot("youbot")
    rng = np.random.default_rng(9)
    for q_true in robot.random_configurations(50, rng):
        q_near = robot.limits.clip(q_true + rng.normal(0.0, 0.02, robot.dof))
        solution = solve_ik(robot, robot.tool_pose(q_true), q_near=q_near)
        np.testing.assert_allclose(solution.q, q_true, atol=1e-6)


def test_closest_of_several_solutions_is_returned():
    robot = get_robot("ur5")
    rng = np.random.default_rng(12)
    q_near = robot.random_configurations(1, rng)[0]
    target = robot.tool_pose(robot.random_configurations(1, rng)[0])
    solution = solve_ik(robot, target, q_near=q_near, min_solutions=4)
    assert len(solution.solutions) == 4
    distances = np.linalg.norm(solution.solutions - q_near, axis=1)
    assert np.linalg.norm(solution.q - q_near) == pytest.approx(distances.min())
    for q in solution.solutions:
        np.testing.assert_allclose(robot.tool_pose(q), target, atol=1e-6)


def test_results_are_reproducible_for_a_seed():
    robot = get_robot("sawyer")
    target = robot.tool_pose(robot.random_configurations(1, np.random.default_rng(3))[0])
    a = solve_ik(robot, target, min_solutions=3, seed=42)
    b = solve_ik(robot, target, min_solutions=3, seed=42)
    np.testing.assert_array_equal(a.solutions, b.solutions)


def test_other_frame_can_be_placed():
    robot = get_robot("sawyer")
    q_true = robot.random_configurations(1, np.random.default_rng(4))[0]
    target = robot.frame_pose(q_true, "right_l6")
    solution = solve_ik(robot, target, frame="right_l6")
    np.testing.assert_allclose(robot.frame_pose(solution.q, "right_l6"), target, atol=1e-6)


@pytest.mark.parametrize(
    ("target", "kwargs", "error", "match"),
    [
        (np.eye(3), {}, InvalidInputError, r"shape \(3,\), or a pose .* shape \(4, 4\)"),
        (np.zeros((3, 1)), {}, InvalidInputError, "got shape"),
        (np.diag([1.0, 1.0, -1.0, 1.0]), {}, InvalidInputError, "rotation matrix"),
        ([0.5, np.inf, 0.2], {}, InvalidInputError, "finite"),
        ([0.5, 0.0, 0.2], {"restarts": -1}, InvalidInputError, "restarts"),
        ([0.5, 0.0, 0.2], {"tolerance": 0.0}, InvalidInputError, "tolerance"),
        ([0.5, 0.0, 0.2], {"tolerance": 10.0}, InvalidInputError, "tolerance"),
        ([0.5, 0.0, 0.2], {"restarts": float("nan")}, InvalidInputError, "restarts"),
        ([0.5, 0.0, 0.2], {"min_solutions": None}, InvalidInputError, "min_solutions"),
        ([0.5, 0.0, 0.2], {"max_iterations": True}, InvalidInputError, "max_iterations"),
        ([0.5, 0.0, 0.2], {"seed": "a"}, InvalidInputError, "seed"),
        ([0.5, 0.0, 0.2], {"seed": -1}, InvalidInputError, "seed"),
        ([0.5, 0.0, 0.2], {"axis": [0.0, 0.0, 0.0]}, InvalidInputError, "axis must be non-zero"),
        ([0.5, 0.0, 0.2], {"q_near": [0.0, 1.0]}, InvalidInputError, "q_near"),
        ([0.5, 0.0, 0.2], {"frame": "nope"}, UnknownNameError, "nope"),
    ],
)
def test_bad_input_raises_typed_errors(target, kwargs, error, match):
    with pytest.raises(error, match=match):
        solve_ik(get_robot("sawyer"), target, **kwargs)


def test_robot_must_be_a_robot():
    with pytest.raises(InvalidInputError, match=r"robots\.Robot"):
        solve_ik("sawyer", [0.5, 0.0, 0.2])


def test_axis_target_leaves_roll_free():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(31)
    for q_true in robot.random_configurations(100, rng):
        T = robot.tool_pose(q_true)
        solution = solve_ik(robot, T[:3, 3], axis=2.0 * T[:3, 2])  # any length: normalised
        got = robot.tool_pose(solution.q)
        np.testing.assert_allclose(got[:3, 3], T[:3, 3], atol=1e-6)
        np.testing.assert_allclose(got[:3, 2], T[:3, 2], atol=1e-6)


@pytest.mark.parametrize("name", ["sawyer", "youbot"])
def test_local_ik_is_solve_ik_without_restarts(name):
    robot = get_robot(name)
    rng = np.random.default_rng(41)
    converged = failed = 0
    for trial in range(60):
        T = robot.tool_pose(robot.random_configurations(1, rng)[0])
        # Reachable targets, and every third one moved off by a few centimetres.
        target = T[:3, 3] + (rng.normal(scale=0.05, size=3) if trial % 3 == 0 else 0.0)
        start = robot.random_configurations(1, rng)[0]
        local = LocalIK(robot, target, axis=T[:3, 2])
        try:
            expected = solve_ik(robot, target, axis=T[:3, 2], q_near=start, restarts=0).q
        except UnreachableError:
            expected = None
        got = local(start)
        if expected is None:
            assert got is None
            failed += 1
        else:
            np.testing.assert_array_equal(got, expected)
            converged += 1
    assert converged >= 10 and failed >= 1


def test_local_ik_checks_its_target_once():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match="axis must be non-zero"):
        LocalIK(robot, [0.5, 0.0, 0.2], axis=[0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="tolerance"):
        LocalIK(robot, [0.5, 0.0, 0.2], tolerance=0.1)
    with pytest.raises(InvalidInputError, match=r"robots\.Robot"):
        LocalIK("sawyer", [0.5, 0.0, 0.2])


def test_abandoning_stalled_restarts_saves_iterations_and_keeps_solutions_valid():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(43)
    saved = 0
    for seed in range(4):
        T = robot.tool_pose(robot.random_configurations(1, rng)[0])
        kwargs = {"axis": T[:3, 2], "min_solutions": 8, "restarts": 24, "seed": seed}
        full = solve_ik(robot, T[:3, 3], **kwargs)
        quick = solve_ik(robot, T[:3, 3], abandon_stalled=True, **kwargs)
        saved += full.iterations - quick.iterations
        for q in quick.solutions:
            pose = robot.tool_pose(q)
            np.testing.assert_allclose(pose[:3, 3], T[:3, 3], rtol=0, atol=1e-9)
            np.testing.assert_allclose(pose[:3, 2], T[:3, 2], rtol=0, atol=1e-9)
            assert robot.limits.contains(q)
        # Reproducible for a seed, like every solve_ik.
        again = solve_ik(robot, T[:3, 3], abandon_stalled=True, **kwargs)
        np.testing.assert_array_equal(again.solutions, quick.solutions)
    assert saved > 0  # stalled restarts were given up early


def test_restarts_in_batches_find_the_solutions_found_one_by_one(monkeypatch):
    # solve_ik keeps batched restarts in order and stops where a one-by-one search would.
    robot = get_robot("sawyer")
    T = robot.tool_pose(robot.random_configurations(1, np.random.default_rng(44))[0])
    kwargs = {"axis": T[:3, 2], "min_solutions": 6, "restarts": 20, "abandon_stalled": True}
    batched = solve_ik(robot, T[:3, 3], **kwargs)
    monkeypatch.setattr(ik_module, "_ONE_BY_ONE", 1000)  # every restart alone
    one_by_one = solve_ik(robot, T[:3, 3], **kwargs)
    assert batched.attempts == one_by_one.attempts
    np.testing.assert_allclose(batched.solutions, one_by_one.solutions, rtol=0, atol=1e-9)


def test_a_target_beyond_any_reach_is_refused_before_the_residuals_overflow():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match=r"\|target x\| must be <= 1000 m, got 1e\+308 m"):
        solve_ik(robot, [1e308, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"\|position z\| must be <= 1000 m"):
        LocalIK(robot, [0.0, 0.0, -2e3])
    with pytest.raises(InvalidInputError, match="seed"):
        solve_ik(robot, [0.5, 0.2, 0.3], seed=True)
