import mujoco
import numpy as np
import pytest

from optraj import physics, problems, robots
from optraj.errors import InvalidInputError
from optraj.physics import static_objects
from optraj.problems.scene_shapes import translation

BALL = (0.75, 0.15, -0.05)


@pytest.fixture(scope="module")
def sawyer():
    return robots.load("sawyer")


def _geom(model, name):
    geom = model.geom(name)
    return int(geom.type[0]), np.asarray(geom.size), np.asarray(geom.pos)


def test_the_ball_rolls_on_cloth_and_planes_and_rebounds_from_the_rest():
    assert static_objects.contact_of(problems.Box("cloth", (1, 1, 1))) == static_objects.ROLLING
    assert static_objects.contact_of(problems.Plane("x", (0, 0, 0))) == static_objects.ROLLING
    assert static_objects.contact_of(problems.Box("block", (1, 1, 1))) == static_objects.REBOUND
    assert static_objects.colour_of("cushion_near") != static_objects.colour_of("cloth")
    assert static_objects.colour_of("block_3") == static_objects.OTHER_COLOUR


def test_every_shape_becomes_its_geom_and_the_ball_rebounds_from_a_block(sawyer):
    turned = translation((1.2, 0.15, -0.05))
    turned[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    scene = problems.Scene(
        (
            problems.Plane("ground", point=(0.0, 0.0, -0.05 - 0.028575)),
            problems.Box("block", (0.3, 0.05, 0.05), turned),  # turned: 0.1 m along x
            problems.Sphere("marble", 0.01, translation((0.75, 0.6, -0.07))),
            problems.Cylinder("post", 0.03, 0.1, translation((0.75, -0.6, 0.0))),
        )
    )
    world = physics.pool_scene(sawyer, BALL, surroundings=scene, kinematic=True).build()
    model = world.model
    kinds = {name: _geom(model, name)[0] for name in ("ground", "block", "marble", "post")}
    assert kinds == {
        "ground": mujoco.mjtGeom.mjGEOM_PLANE,
        "block": mujoco.mjtGeom.mjGEOM_BOX,
        "marble": mujoco.mjtGeom.mjGEOM_SPHERE,
        "post": mujoco.mjtGeom.mjGEOM_CYLINDER,
    }
    np.testing.assert_allclose(_geom(model, "post")[1][:2], [0.03, 0.1])
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(
        data.geom_xmat[model.geom("block").id].reshape(3, 3), turned[:3, :3], atol=1e-12
    )
    # The ball rolls on the plane along +x into the block (its face at x = 1.15 m) and back.
    record = physics.straight_cue(world.scene, (1.0, 0.0, 0.0), 1.0)
    outcome = physics.outcome(record, problems.sawyer_pool_shot(1.0))
    assert outcome.roll[:, 0].max() < 1.15 - 0.028575 + 1e-3
    assert outcome.roll[-1, 0] < outcome.roll[:, 0].max() - 0.05


def test_a_strike_world_refuses_carried_objects(sawyer):
    block = problems.Box("block_0", (0.01, 0.01, 0.01), translation((1.0, 0.0, 0.0)))
    carried = problems.Scene((block,), (problems.Attachment("block_0", "right_hand", 0.0, 1.0),))
    with pytest.raises(InvalidInputError, match="'block_0' to the robot"):
        physics.pool_scene(sawyer, BALL, surroundings=carried).build()
