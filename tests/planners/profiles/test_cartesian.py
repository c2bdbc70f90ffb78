"""Tests of planners.profiles.cartesian: straight lines with SLERP, LinearTrajectory."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from optraj import problems, robots
from optraj.errors import (
    InfeasibleError,
    InvalidInputError,
    PathJumpError,
    PathJumpWarning,
    UnknownNameError,
)
from optraj.planners.checker import check
from optraj.planners.profiles.cartesian import (
    CartesianStraightLine,
    LinearTrajectory,
    follow_tool_path,
    path_scaling,
)


def _line_problem(seed: int, **kwargs):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(seed)
    start = robot.tool_pose(robot.home)
    goal = start.copy()
    goal[:3, 3] += rng.uniform(-0.12, 0.12, 3)
    goal[:3, :3] = start[:3, :3] @ pin.exp3(rng.uniform(-0.3, 0.3, 3))
    return problems.CartesianLine(robot, start, goal, q_start=robot.home, **kwargs)


@pytest.mark.parametrize("profile", ["cubic", "quintic", "lspb"])
def test_path_scalings_are_rest_to_rest_and_consistent(profile):
    tau = np.linspace(0.0, 1.0, 20001)
    s, ds, dds = path_scaling(profile, tau)
    assert (s[0], s[-1], ds[0], ds[-1]) == pytest.approx((0.0, 1.0, 0.0, 0.0), abs=1e-12)
    np.testing.assert_allclose(np.gradient(s, tau)[1:-1], ds[1:-1], atol=1e-3)
    # Integrate the acceleration back to the velocity (trapezoid rule).
    integrated = np.concatenate([[0.0], np.cumsum(0.5 * (dds[1:] + dds[:-1]) * np.diff(tau))])
    np.testing.assert_allclose(integrated, ds, atol=1e-3)


@pytest.mark.parametrize(("profile", "quantities"), [
    ("cubic", ("position", "velocity", "acceleration")),
    ("quintic", ("position", "velocity", "acceleration", "jerk")),
    ("lspb", ("position", "velocity", "acceleration")),
])  # fmt: skip
def test_lines_follow_the_segment_within_limits(profile, quantities):
    for seed in range(5):
        problem = _line_problem(seed)
        traj = CartesianStraightLine(profile).plan(problem)
        report = check(traj, problem, quantities=quantities)
        assert report.ok, report.summary()
        # Tight: the interpolated joint path stays within 1e-7 m of the line.
        assert report["tool path position"].value < 1e-7


def _narrowed_line(seed: int, joint_name: str) -> problems.CartesianLine:
    """Line ``seed`` on a Sawyer whose joint may turn only half as far as the free line turns
    it: the inverse kinematics then pins the joint on that limit for the second half while
    the other six keep the tool on the line."""
    sawyer = get_robot("sawyer")
    free = _line_problem(seed)
    line = CartesianStraightLine("quintic").plan(free)
    end = line.sample(np.array([line.duration])).q[0]
    joint = sawyer.joint_names.index(joint_name)
    turn = end[joint] - sawyer.home[joint]
    assert abs(turn) > 0.1
    lower, upper = sawyer.limits.lower.copy(), sawyer.limits.upper.copy()
    (upper if turn > 0 else lower)[joint] = sawyer.home[joint] + 0.5 * turn
    narrow = robots.Robot(
        "sawyer",
        sawyer.model,
        replace(sawyer.limits, lower=lower, upper=upper),
        sawyer.tool_frame,
        {"home": sawyer.home},
    )
    return problems.CartesianLine(narrow, free.T_start, free.T_goal, q_start=sawyer.home)


def test_a_joint_held_at_its_limit_stays_there_between_samples():
    # Rates that ignore the hold drive the spline past the limit between samples.
    problem = _narrowed_line(2, "right_j1")
    traj = CartesianStraightLine("quintic").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    assert report["position"].joint == "right_j1"
    assert report["position"].margin < 1e-9  # on the limit, not short of it


def test_a_line_that_kinks_past_a_limit_is_refused():
    # Here the joint reaches its limit while moving fast: the joint path kinks there and the
    # spline through the samples passes the limit, at any duration.
    problem = _narrowed_line(3, "right_j4")
    with pytest.raises(InfeasibleError, match="leaves the position limits") as info:
        CartesianStraightLine("quintic").plan(problem)
    assert (info.value.limit, info.value.joint) == ("position", "right_j4")
    assert info.value.required < info.value.allowed == problem.limits.lower[4]


def test_speed_cap_sets_the_duration():
    problem = _line_problem(1, speed=0.05)
    traj = CartesianStraightLine("quintic").plan(problem)
    assert traj.duration == pytest.approx(problem.length * 1.875 / 0.05, rel=1e-12)
    speeds = np.linalg.norm(
        get_robot("sawyer").jacobian(traj.sample(traj.times(200.0)).q)[:, :3]
        @ traj.sample(traj.times(200.0)).qd[:, :, None],
        axis=1,
    )
    assert speeds.max() == pytest.approx(0.05, rel=1e-4)


def test_duration_and_speed_disagreeing_is_infeasible():
    problem = _line_problem(2, speed=0.01, duration=0.5)
    with pytest.raises(InfeasibleError, match="above the speed cap"):
        CartesianStraightLine("cubic").plan(problem)


def test_fixed_duration_too_short_for_the_joints_is_infeasible():
    problem = _line_problem(3, duration=0.01)
    with pytest.raises(InfeasibleError, match="breaks a joint limit"):
        CartesianStraightLine("cubic").plan(problem)


def _over_the_base_axis():
    # youBot, gripper pointing up (candle orientation), a line passing over the J1 axis:
    # the arm must swing over to the other side, which no continuous joint motion does.
    robot = get_robot("youbot")
    start = robot.tool_pose(robot.home)
    goal = start.copy()
    start[:3, 3] = [0.024, -0.04, 0.5]
    goal[:3, 3] = [0.024, 0.04, 0.5]
    return problems.CartesianLine(robot, start, goal)


def test_line_over_a_singularity_reports_the_jump():
    with pytest.raises(PathJumpError, match="arm_joint_3") as info:
        CartesianStraightLine("cubic").plan(_over_the_base_axis())
    assert info.value.jump > 3.0 > info.value.threshold
    assert 0.0 < info.value.time < 1.0


def test_jump_can_be_a_warning():
    with pytest.warns(PathJumpWarning, match="jumps"):
        CartesianStraightLine("cubic", on_jump="warn").plan(_over_the_base_axis())


def test_bad_settings_are_rejected():
    with pytest.raises(UnknownNameError, match="cubic, quintic, lspb"):
        CartesianStraightLine("septic")
    with pytest.raises(InvalidInputError, match="samples"):
        CartesianStraightLine(samples=3)
    with pytest.raises(InvalidInputError, match="CartesianLine"):
        CartesianStraightLine().plan(problems.ece486_paddle_strike())


# ------------------------------------------------------------- the pull-back LinearTrajectory


def test_linear_trajectory_has_the_seed_semantics():
    line = LinearTrajectory([0.1, 0.2, 0.3], [0.4, 0.2, 0.3], speed=0.5, orientation=np.eye(3))
    assert line.duration == pytest.approx(0.6)
    position, velocity, acceleration = line.sample([0.0, 0.3, 0.6, 0.9])
    np.testing.assert_allclose(position[:, 0], [0.1, 0.25, 0.4, 0.4])
    np.testing.assert_allclose(velocity[:, 0], [0.5, 0.5, 0.5, 0.0])  # full speed at t = 0
    np.testing.assert_array_equal(acceleration, 0.0)
    with pytest.raises(InvalidInputError, match="t must be >= 0"):
        line.sample(-0.1)
    with pytest.raises(InvalidInputError, match="differ"):
        LinearTrajectory([0, 0, 0], [0, 0, 0], 1.0, np.eye(3))


def test_linear_trajectory_from_rest_needs_unbounded_acceleration():
    robot = get_robot("sawyer")
    start = robot.tool_pose(robot.home)
    line = LinearTrajectory(start[:3, 3], start[:3, 3] + [0.1, 0.0, 0.0], 0.5, start[:3, :3])
    traj = line.to_joints(robot, robot.home)
    problem = problems.PointToPoint(robot, robot.home, traj.sample(traj.duration).q)
    report = check(traj, problem, quantities=("position", "velocity", "acceleration"))
    assert not report["start state"].ok  # it starts at full speed
    assert report["acceleration"].value == np.inf
    assert "jumps" in report["acceleration"].detail
    # The line itself is followed: tool speed 0.5 m/s along +x.
    sample = traj.sample(np.linspace(0.0, traj.duration, 50))
    tool_velocity = np.einsum("mij,mj->mi", robot.jacobian(sample.q)[:, :3], sample.qd)
    np.testing.assert_allclose(tool_velocity, np.tile([0.5, 0.0, 0.0], (50, 1)), atol=1e-6)


def test_settings_are_checked_when_built():
    # issue 32, defect 6: an unknown on_jump passed until a jump; extremes crashed the maths
    with pytest.raises(UnknownNameError, match="on_jump policy"):
        CartesianStraightLine(on_jump="ignore")
    with pytest.raises(InvalidInputError, match="samples must be an integer <= 100000"):
        CartesianStraightLine(samples=10**7)
    with pytest.raises(InvalidInputError, match="jump_threshold must be a numeric"):
        CartesianStraightLine(jump_threshold="0.1")
    with pytest.raises(InvalidInputError, match="speed must be <= 343 m/s"):
        LinearTrajectory(np.zeros(3), np.ones(3), 1e308, np.eye(3))
    with pytest.raises(InvalidInputError, match=r"\|end - start\| / speed must be <= 86400 s"):
        LinearTrajectory(np.zeros(3), np.ones(3), 1e-200, np.eye(3))
    line = LinearTrajectory(np.zeros(3), np.ones(3), 1.0, np.eye(3))
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match="samples must be an integer >= 1"):
        line.to_joints(robot, robot.home, samples=-1)
    pose = robot.tool_pose(robot.home)
    arrays = (np.array([pose, pose]), np.zeros((2, 6)), np.zeros((2, 6)), robot.home)
    with pytest.raises(InvalidInputError, match="jump_threshold must be a numeric"):
        follow_tool_path(robot, [0.0, 1.0], *arrays, jump_threshold="0.1")
    with pytest.raises(InvalidInputError, match="times must be increasing"):
        follow_tool_path(robot, [1.0, 0.0], *arrays)


def test_a_still_line_without_a_duration_is_refused_and_with_one_held():
    # issue 32, defects 8 and 6: a zero-length line at Sawyer's stretched-out q = 0 raised
    # numpy's LinAlgError (J J^T singular); elsewhere it planned a 4e-5 s trajectory
    robot = get_robot("sawyer")
    q = np.zeros(robot.dof)
    pose = robot.tool_pose(q)
    still = problems.CartesianLine(robot, pose, pose, q_start=q)
    with pytest.raises(InvalidInputError, match="T_goal equals T_start"):
        CartesianStraightLine().plan(still)
    held = problems.CartesianLine(robot, pose, pose, q_start=q, duration=0.5)
    traj = CartesianStraightLine().plan(held)
    assert traj.duration == pytest.approx(0.5)
    assert check(traj, held, quantities=("position", "velocity", "acceleration")).ok


def test_a_line_at_its_speed_cap_passes_the_checkers_tool_speed():
    # A fuzz finding of issue 32: the IK-sampled joint path took the tool 6.5e-7 m/s over
    # a 1 m/s cap, and the checker failed the plan.
    robot = get_robot("paddle4")
    problem = problems.CartesianLine(
        robot,
        [[0, 0, 1, 1.0], [1, 0, 0, 0], [0, 1, 0, 0.3], [0, 0, 0, 1]],
        [
            [-0.18640329676226966, 0.0, 0.9824733131012553, 1.089508459030042],
            [0.9824733131012553, 0.0, 0.18640329676226966, 0.3774666759435965],
            [0.0, 1.0, 0.0, 0.3],
            [0.0, 0.0, 0.0, 1.0],
        ],
        q_start=[0.5, 0.0, 0.75, 0.0],
        speed=1.0,
    )
    traj = CartesianStraightLine("lspb").plan(problem)
    report = check(traj, problem, quantities=("position", "velocity", "acceleration"))
    assert report["tool speed"].value <= 1.0
    assert report.ok, report
