import dataclasses

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from optraj import physics, problems, robots
from optraj.errors import InvalidInputError
from optraj.problems.scene_shapes import translation
from optraj.problems.scenes import BALL_FROM_NEAR_END
from optraj.robots.collision import CUE_TIP_RADIUS

BALL = (0.75, 0.15, -0.05)


@pytest.fixture(scope="module")
def sawyer():
    return robots.load("sawyer")


def _mass_and_gravity(world, q):
    data = mujoco.MjData(world.model)
    data.qpos[world.arm_qpos] = q
    mujoco.mj_forward(world.model, data)
    M = np.zeros((world.model.nv, world.model.nv))
    mujoco.mj_fullM(world.model, data, M)
    dofs = world.arm_dof
    return M[np.ix_(dofs, dofs)], data.qfrc_bias[dofs], data


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_the_scene_arm_has_the_robot_models_dynamics(name):
    robot = robots.load(name)
    ball = BALL if name == "sawyer" else (0.8, 0.2, 0.3)
    scene = physics.pool_scene if name == "sawyer" else physics.paddle_scene
    world = scene(robot, ball).build()
    rng = np.random.default_rng(3)
    for q in robot.random_configurations(5, rng):
        M, g, _ = _mass_and_gravity(world, q)
        upper = pin.crba(robot.model, robot.data, q)
        expected = np.triu(upper) + np.triu(upper, 1).T
        # Only the striking geoms' 1e-6 kg differ from Pinocchio's model (cue included).
        np.testing.assert_allclose(M, expected, atol=1e-5)
        np.testing.assert_allclose(
            g, pin.computeGeneralizedGravity(robot.model, robot.data, q), atol=1e-4
        )


def test_the_cue_tip_front_is_the_tool_frame(sawyer):
    world = physics.pool_scene(sawyer, BALL).build()
    q = sawyer.random_configurations(1, np.random.default_rng(5))[0]
    _, _, data = _mass_and_gravity(world, q)
    T = sawyer.tool_pose(q)
    centre = data.geom_xpos[world.tool_geom]
    np.testing.assert_allclose(centre + CUE_TIP_RADIUS * T[:3, 2], T[:3, 3], atol=1e-9)


def test_model_error_scales_the_links_and_adds_the_payload(sawyer):
    nominal = physics.pool_scene(sawyer, BALL).build().model
    heavy = physics.pool_scene(sawyer, BALL, mass_scale=1.1, payload=0.2).build().model
    arm = [nominal.body(name).id for name in ("right_l0", "right_l3")]
    np.testing.assert_allclose(heavy.body_mass[arm], 1.1 * nominal.body_mass[arm])
    links = [nominal.body(f"right_l{i}").id for i in range(7)]
    added = heavy.body_mass.sum() - nominal.body_mass.sum()
    assert added == pytest.approx(0.1 * nominal.body_mass[links].sum() + 0.2, rel=1e-9)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"mass_scale": -1.0}, "mass_scale"),
        ({"payload": -0.1}, "payload"),
        ({"step": 0.0}, "step"),
        ({"fine_step": 1e-3}, "fine_step"),
        ({"kinematic": "yes"}, "kinematic"),
        # a step that MuJoCo would take forever with, or that misses the 2 ms contact
        ({"step": 1e-300, "fine_step": 1e-300}, r"step must be >= 1e-07 s, got 1e-300 s"),
        ({"step": 0.01}, r"step must be <= 0\.001 s, got 0\.01 s"),
        ({"payload": True}, "payload must be a numeric"),
    ],
)
def test_bad_scene_options_are_typed_errors(sawyer, options, match):
    with pytest.raises(InvalidInputError, match=match):
        physics.pool_scene(sawyer, BALL, **options)


def test_scene_for_refuses_other_problems():
    with pytest.raises(InvalidInputError, match="PoolStrike or a PaddleStrike"):
        physics.scene_for(object())


def _geom(model, name):
    geom = model.geom(name)
    return int(geom.type[0]), np.asarray(geom.size), np.asarray(geom.pos)


def test_the_pool_world_is_built_from_the_ready_made_table(sawyer):
    model = physics.pool_scene(sawyer, BALL).build().model
    table = problems.pool_table(BALL)
    for name in ("cloth", "cushion_far", "cushion_near", "cushion_left", "cushion_right"):
        kind, size, pos = _geom(model, name)
        box = table.object(name)
        assert kind == mujoco.mjtGeom.mjGEOM_BOX
        np.testing.assert_array_equal(size, box.half_extents)
        np.testing.assert_array_equal(pos, box.pose[:3, 3])
        # the ball touches each of them through its own pair, nothing else does
        assert model.pair(f"{name}-ball").id >= 0
    kind, _, pos = _geom(model, "floor")
    assert kind == mujoco.mjtGeom.mjGEOM_PLANE and pos[2] == table.object("floor").point[2]
    assert model.npair == 1 + 6  # cue tip and ball; ball and each of the 6 table objects
    assert (model.geom_contype == 0).all() and (model.geom_conaffinity == 0).all()


def test_the_table_follows_the_ball_unless_the_problem_has_its_own(sawyer, pool_shot):
    moved = physics.pool_scene(sawyer, BALL).with_ball((0.85, 0.15, -0.05)).build().model
    _, _, pos = _geom(moved, "cushion_near")
    assert pos[0] == pytest.approx(0.85 - BALL_FROM_NEAR_END - 0.05)
    # The README shot's wrist is inside the ready-made table's cloth (the problem refuses
    # that table), so this problem has a block far ahead instead.
    block = problems.Box("block", (0.05, 0.05, 0.05), translation((2.0, 0.15, 0.0)))
    own = problems.Scene((block,))
    scene = physics.scene_for(dataclasses.replace(pool_shot, scene=own))
    assert scene.surroundings is own
    model = scene.with_ball(BALL).build().model
    _, _, pos = _geom(model, "block")
    np.testing.assert_array_equal(pos, [2.0, 0.15, 0.0])
    assert model.npair == 2 and "cloth" not in {model.geom(i).name for i in range(model.ngeom)}


def test_other_surroundings_are_refused(sawyer):
    with pytest.raises(InvalidInputError, match=r"surroundings must be a problems\.Scene"):
        physics.pool_scene(sawyer, BALL, surroundings=[problems.Plane("floor", (0, 0, -1))])


def test_a_paddle_world_has_no_table_by_default():
    paddle = robots.load("paddle4")
    model = physics.paddle_scene(paddle, (0.8, 0.2, 0.3)).build().model
    assert model.npair == 1  # blade and ball
