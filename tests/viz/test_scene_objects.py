import dataclasses

import numpy as np
import pytest
from viz_support import pool_case, youbot_case

from optraj import problems
from optraj.problems.scene_shapes import translation
from optraj.viz.scene_objects import drawn_name, object_shapes
from optraj.viz.tasks import task_objects


@pytest.fixture(scope="module")
def pool():
    return pool_case()


@pytest.fixture(scope="module")
def youbot():
    return youbot_case()


def test_table_parts_are_drawn_under_table():
    assert drawn_name("cushion_left") == "table/cushion_left"
    assert drawn_name("cloth") == "table/cloth"
    assert drawn_name("block_0") == "block_0"


def test_a_problems_own_scene_is_drawn_and_its_planes_are_tiles(pool):
    shot, traj = pool
    turned = translation((1.5, 0.4, -0.05))
    turned[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    scene = problems.Scene(
        (
            problems.Box("crate", (0.1, 0.05, 0.02), turned),
            problems.Cylinder("post", 0.03, 0.2, translation((1.5, -0.4, 0.0))),
            problems.Plane("wall", point=(2.5, 0.0, 0.0), normal=(-1.0, 0.0, 0.0)),
            problems.Plane("floor", point=(0.0, 0.0, -0.914)),
        )
    )
    drawn = object_shapes(scene, shot.robot, traj, np.zeros(1), -0.914)
    shapes = {s.name: s for s in drawn}
    assert set(shapes) == {"crate", "post", "wall"}  # the floor plane is the drawn floor
    np.testing.assert_array_equal(shapes["crate"].pose, turned)
    assert shapes["crate"].size == (0.2, 0.1, 0.04)
    assert shapes["post"].kind == "cylinder" and shapes["post"].size == (0.03, 0.4)
    wall = shapes["wall"]  # its top face lies on the plane, facing -x
    np.testing.assert_allclose(wall.pose[:3, 2], [-1.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(wall.pose[0, 3] - wall.size[2] / 2, 2.5, atol=1e-12)


def test_an_attachment_by_time_and_a_missing_phase(youbot):
    problem, traj = youbot
    block = problems.Box("block_0", (0.01, 0.01, 0.01), translation(problem.picks[0]))
    tool = problem.robot.model.frames[problem.robot.tool_frame_id].name
    scene = problems.Scene(
        (block,),
        (
            problems.Attachment("block_0", tool, 1.0, 2.0),
            problems.Attachment("block_0", tool, "no_such_phase", "release_0"),
        ),
    )
    mine = dataclasses.replace(problem, scene=scene)
    times = np.linspace(0.0, traj.duration, 200)
    (shape,) = task_objects(mine, mine.robot, traj, times, -0.2)
    assert shape.motion is not None
    moved = np.linalg.norm(shape.motion[:, :3, 3] - problem.picks[0], axis=1) > 1e-9
    assert not moved[times < 1.0].any() and moved[(times > 1.0) & (times < 2.0)].all()
    after = shape.motion[times > 2.0]
    np.testing.assert_array_equal(after, np.broadcast_to(after[0], after.shape))  # left there
