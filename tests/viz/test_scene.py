import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot
from viz_support import paddle_case, pool_case, rolled_outcome, youbot_case

from optraj import planners
from optraj.errors import InvalidInputError
from optraj.viz.scene import MAX_AFTER, build_scene

CASES = {"pool": pool_case, "paddle": paddle_case, "youbot": youbot_case}


def _lowest_point(geometry_object, T):
    """Lowest z of a placed coal shape [m]."""
    shape = geometry_object.geometry
    R, z = T[:3, :3], T[2, 3]
    kind = type(shape).__name__
    if kind == "Sphere":
        return z - shape.radius
    if kind == "Box":
        return z - np.abs(R[2, :]) @ shape.halfSide
    tilt = np.sqrt(max(0.0, 1.0 - R[2, 2] ** 2))
    reach = shape.halfLength * abs(R[2, 2])
    if kind == "Capsule":
        return z - reach - shape.radius
    return z - reach - shape.radius * tilt


@pytest.mark.parametrize("case", sorted(CASES))
def test_nothing_goes_below_the_floor(case):
    problem, traj = CASES[case]()
    scene = build_scene(problem.robot, traj, problem, fps=10.0)
    floor = scene.shape("floor")
    top = floor.pose[2, 3] + floor.size[2] / 2
    model, data = scene.robot.model, scene.robot.model.createData()
    placements = pin.GeometryData(scene.geometry)
    lowest = np.inf
    for q in scene.q:
        pin.forwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, scene.geometry, placements)
        for i, item in enumerate(scene.geometry.geometryObjects):
            lowest = min(lowest, _lowest_point(item, placements.oMg[i].homogeneous))
    assert lowest >= top - 1e-9, f"{case}: robot reaches {lowest:.4f} m, floor at {top:.4f} m"
    for shape in scene.shapes:
        if shape.name != "floor" and shape.kind in ("box", "sphere"):
            half = shape.size[2] / 2 if shape.kind == "box" else shape.size[0]
            assert shape.pose[2, 3] - half >= top - 1e-9, shape.name


def test_pool_scene_holds_table_ball_line_and_frames_the_action():
    shot, traj = pool_case()
    scene = build_scene(shot.robot, traj, shot, fps=30.0)
    names = {shape.name for shape in scene.shapes}
    assert {"floor", "pedestal", "table/cloth", "ball", "strike_line"} <= names
    assert scene.q.shape == (len(scene.times), 7)
    np.testing.assert_allclose(scene.times[-1], traj.duration)
    assert np.all(np.diff(scene.times) <= 1.0 / 30.0 + 1e-12)
    # The camera looks at a point between the robot's base and the ball, from outside.
    assert 0.0 < scene.target[0] < shot.ball[0]
    assert np.linalg.norm(scene.camera - scene.target) > 1.0


def test_an_outcome_adds_the_ball_path_and_moves_the_ball():
    shot, traj = pool_case()
    outcome = rolled_outcome(shot, contact_time=traj.phase("strike").t_start + 0.1)
    scene = build_scene(shot.robot, traj, shot, outcome, fps=20.0)
    ball = scene.shape("ball")
    assert ball.motion is not None and len(ball.motion) == len(scene.times)
    np.testing.assert_allclose(ball.motion[0][:3, 3], shot.ball)
    np.testing.assert_allclose(ball.motion[-1][:3, 3], outcome.roll[-1], atol=1e-9)
    assert any(shape.name.startswith("ball_path/") for shape in scene.shapes)
    assert traj.duration <= scene.times[-1] <= traj.duration + MAX_AFTER
    np.testing.assert_allclose(scene.q[-1], traj.sample(traj.duration).q)


def test_a_still_scene_has_one_frame():
    problem, traj = youbot_case()
    scene = build_scene(problem.robot, traj, problem, at=3.0)
    np.testing.assert_allclose(scene.times, [3.0])
    np.testing.assert_allclose(scene.q[0], traj.sample(3.0).q)


def test_the_robot_alone_has_only_its_mount():
    robot = get_robot("sawyer")
    traj = planners.Trajectory.constant(robot.home, 1.0)
    scene = build_scene(robot, traj)
    assert {shape.name for shape in scene.shapes} == {"floor", "pedestal"}


def test_bad_input_is_refused_with_the_value_named():
    shot, traj = pool_case()
    robot = shot.robot
    with pytest.raises(InvalidInputError, match="fps"):
        build_scene(robot, traj, shot, fps=1000.0)
    with pytest.raises(InvalidInputError, match="robot 'youbot' has 5"):
        build_scene(get_robot("youbot"), traj)
    with pytest.raises(InvalidInputError, match=r"trajectory must be a planners\.Trajectory"):
        build_scene(robot, "plan")
    with pytest.raises(InvalidInputError, match="problem must be"):
        build_scene(robot, traj, problem="shot")
    paddle, _ = paddle_case()
    with pytest.raises(InvalidInputError, match="for robot 'paddle4'"):
        build_scene(robot, traj, paddle)
    with pytest.raises(InvalidInputError, match="outcome must be"):
        build_scene(robot, traj, shot, outcome=3)
    with pytest.raises(InvalidInputError, match="at"):
        build_scene(robot, traj, shot, at=traj.duration + 1.0)
    with pytest.raises(InvalidInputError, match="view"):
        build_scene(robot, traj, shot, view=(0.0, 0.0, 0.0))
    with pytest.raises(InvalidInputError, match="no shape 'chair'"):
        build_scene(robot, traj, shot).shape("chair")
