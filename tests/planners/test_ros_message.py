"""Tests of planners.ros_message: the ROS 2 JointTrajectory dict and YAML, and reading them back."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Trajectory
from optraj.robots import SymbolicModel

# Fields of trajectory_msgs/msg/JointTrajectory and JointTrajectoryPoint in ROS 2
# (ros2/common_interfaces), std_msgs/msg/Header and builtin_interfaces/msg/Time and Duration.
MESSAGE = {"header", "joint_names", "points"}
HEADER = {"stamp", "frame_id"}
POINT = {"positions", "velocities", "accelerations", "effort", "time_from_start"}
TIME = {"sec", "nanosec"}


def _paddle_move() -> Trajectory:
    """A C2 quintic move of paddle4 with a breakpoint off any round time."""
    robot = get_robot("paddle4")
    rng = np.random.default_rng(5)
    q = robot.home + rng.uniform(-0.2, 0.2, (3, 4))
    q[:, [0, 2]] = np.abs(q[:, [0, 2]])  # prismatic joints within [0, 1] m
    qd, qdd = rng.normal(size=(3, 4)), rng.normal(size=(3, 4))
    qd[[0, -1]] = qdd[[0, -1]] = 0.0
    return Trajectory.from_hermite([0.0, 0.437, 1.2], q, qd, qdd, joint_names=robot.joint_names)


def _seconds(point) -> float:
    return point["time_from_start"]["sec"] + point["time_from_start"]["nanosec"] * 1e-9


def test_the_message_has_the_ros2_fields_and_plain_values():
    traj = Trajectory([0.0, 1.5], [[[0.0, 1.0], [1.0, 0.0]]], joint_names=("a", "b"))
    message = traj.to_ros(rate=2.0)
    assert set(message) == MESSAGE
    assert set(message["header"]) == HEADER and message["header"]["frame_id"] == ""
    assert message["header"]["stamp"] == {"sec": 0, "nanosec": 0}
    assert message["joint_names"] == ["a", "b"]
    assert all(set(p) == POINT and set(p["time_from_start"]) == TIME for p in message["points"])
    assert [p["time_from_start"] for p in message["points"]] == [
        {"sec": 0, "nanosec": 0},
        {"sec": 0, "nanosec": 500_000_000},
        {"sec": 1, "nanosec": 0},
        {"sec": 1, "nanosec": 500_000_000},
    ]
    assert message["points"][1]["positions"] == [0.5, 1.0]
    assert message["points"][1]["velocities"] == [1.0, 0.0]
    assert message["points"][1]["accelerations"] == [0.0, 0.0]
    assert all(p["effort"] == [] for p in message["points"])  # no robot: empty, as in ROS
    assert json.loads(json.dumps(message)) == message  # plain data
    assert type(message["points"][3]["time_from_start"]["nanosec"]) is int


def test_points_are_the_csv_rows_at_a_rate_and_the_breakpoints_without(tmp_path):
    traj = _paddle_move()
    traj.to_csv(tmp_path / "t.csv", rate=30.0)
    rows = np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)
    points = traj.to_ros(rate=30.0)["points"]
    np.testing.assert_allclose([_seconds(p) for p in points], rows[:, 0], rtol=0.0, atol=5e-10)
    np.testing.assert_array_equal([p["positions"] for p in points], rows[:, 1:5])
    np.testing.assert_array_equal([p["velocities"] for p in points], rows[:, 5:9])
    np.testing.assert_array_equal([p["accelerations"] for p in points], rows[:, 9:13])
    exact = traj.to_ros()["points"]
    np.testing.assert_allclose([_seconds(p) for p in exact], traj.breakpoints, atol=5e-10)


def test_efforts_are_the_robots_inverse_dynamics():
    robot = get_robot("paddle4")
    traj = _paddle_move()
    points = traj.to_ros(rate=20.0, robot=robot)["points"]
    rnea = SymbolicModel(robot.model).rnea()  # the CasADi RNEA, built apart from Pinocchio's
    for point in points:
        tau = rnea(point["positions"], point["velocities"], point["accelerations"])
        np.testing.assert_allclose(point["effort"], np.asarray(tau).ravel(), atol=1e-9)
    # At rest, the vertical prismatic joint J1 carries the weight of everything above it.
    still = Trajectory.constant(robot.home, 1.0).to_ros(robot=robot)["points"][0]["effort"]
    mass = sum(inertia.mass for inertia in list(robot.model.inertias)[1:])
    np.testing.assert_allclose(still, [mass * 9.81, 0.0, 0.0, 0.0], atol=1e-9)


def test_joint_names_come_from_the_argument_the_robot_or_the_trajectory():
    robot = get_robot("paddle4")
    traj = Trajectory.constant(robot.home, 1.0)  # default names q0 .. q3
    assert traj.to_ros()["joint_names"] == ["q0", "q1", "q2", "q3"]
    assert traj.to_ros(robot=robot)["joint_names"] == list(robot.joint_names)
    assert traj.to_ros(robot=robot, joint_names=list("abcd"))["joint_names"] == list("abcd")


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"robot": "paddle4"}, "robot must be a robots.Robot, got str"),
        ({"robot": "sawyer"}, "robot 'sawyer' has 7 joints, the trajectory 4"),
        ({"joint_names": ["a"]}, "joint_names must name the 4 joints, got 1 names"),
        ({"rate": -1.0}, "rate must be > 0 Hz"),
    ],
)
def test_bad_arguments_are_typed_errors(kwargs, match):
    if kwargs.get("robot") == "sawyer":
        kwargs = {"robot": get_robot("sawyer")}
    traj = Trajectory.constant(np.zeros(4), 1.0)
    with pytest.raises(InvalidInputError, match=match):
        traj.to_ros(**kwargs)


def test_the_dict_reads_back_exactly_at_the_breakpoints_of_a_c2_quintic():
    traj = _paddle_move()
    back = Trajectory.from_ros(traj.to_ros())
    assert back.joint_names == traj.joint_names and back.degree == 5
    grid = np.linspace(0.0, traj.duration, 2001)
    for ours, theirs in zip(traj.sample(grid)[1:4], back.sample(grid)[1:4], strict=True):
        np.testing.assert_allclose(theirs, ours, atol=1e-8, rtol=0.0)


def test_yaml_round_trip_equals_the_dict_round_trip(tmp_path):
    robot = get_robot("paddle4")
    middle = 0.5 * (robot.limits.lower + robot.limits.upper)
    plan = planners.Ruckig().plan(problems.PointToPoint(robot, middle, middle + 0.1))
    path = tmp_path / "plan.yaml"
    text = plan.to_ros_yaml(path, rate=100.0, robot=robot)
    assert path.read_text() == text
    assert yaml.safe_load(text) == plan.to_ros(100.0, robot=robot)  # floats read back exactly
    from_file, from_dict = Trajectory.from_ros(path), Trajectory.from_ros(yaml.safe_load(text))
    grid = np.linspace(0.0, plan.duration, 3001)
    np.testing.assert_array_equal(from_file.sample(grid).q, from_dict.sample(grid).q)
    # Within the CSV bound (tests/planners/test_export_csv.py): 0.45 jerk limit h^3.
    error = np.abs(from_file.sample(grid).q - plan.sample(grid).q).max(axis=0)
    assert np.all(error <= 0.45 * robot.limits.jerk * 0.01**3)


def test_reading_a_file_that_is_not_yaml_names_it(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("points: [1, 2\n")
    with pytest.raises(InvalidInputError, match=rf"^'{path}' is not YAML: "):
        Trajectory.from_ros(path)
    path.write_text("- 1\n- 2\n")
    with pytest.raises(InvalidInputError, match=rf"^'{path}': a JointTrajectory must be a map"):
        Trajectory.from_ros(str(path))
    with pytest.raises(InvalidInputError, match="no trajectory file at"):
        Trajectory.from_ros(tmp_path / "missing.yaml")
    with pytest.raises(InvalidInputError, match="message must be a str or a Path, got int 5"):
        Trajectory.from_ros(5)
    with pytest.raises(InvalidInputError, match=r"cannot write .*: Is a directory"):
        Trajectory.constant([0.0], 1.0).to_ros_yaml(tmp_path)
