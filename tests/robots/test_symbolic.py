"""Tests of robots.symbolic.SymbolicModel against Pinocchio's numeric algorithms."""

from __future__ import annotations

import pickle
from collections.abc import Callable
from dataclasses import dataclass

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest
from conftest import race

from optraj import robots
from optraj.errors import InvalidInputError, UnknownNameError, UnsupportedModelError
from optraj.robots.symbolic import SymbolicModel

ROBOT_NAMES = ["paddle4", "sawyer", "youbot", "panda", "ur5"]
OPTIONAL_ROBOTS = {"panda", "ur5"}  # need example-robot-data
HANDMADE = "handmade"
N_SAMPLES = 200
SEED = 20_240_611
ATOL = 1e-9
FD_STEP = 1e-6
FD_ATOL = 1e-6

MIMIC_URDF = """<?xml version="1.0"?>
<robot name="mimic_pair">
  <link name="base"/>
  <link name="l1">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <link name="l2">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/>
    <mimic joint="j1" multiplier="2" offset="0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


@dataclass
class Case:
    """One model with its symbolic functions and a fixed set of random samples."""

    name: str
    model: pin.Model
    sym: SymbolicModel
    tool_frame: str
    tool_id: int
    mid_id: int
    qs: np.ndarray
    vs: np.ndarray
    accs: np.ndarray


def _handmade_model() -> tuple[pin.Model, str]:
    """Branching tree with every supported joint type, incl. youBot-like unaligned joints."""
    rng = np.random.default_rng(7)
    model = pin.Model()
    model.name = "handmade"

    def placement() -> pin.SE3:
        return pin.SE3(pin.exp3(rng.normal(size=3)), 0.3 * rng.normal(size=3))

    def inertia() -> pin.Inertia:
        a = rng.normal(size=(3, 3))
        rotational = a @ a.T + 0.1 * np.eye(3)
        return pin.Inertia(rng.uniform(0.5, 3.0), 0.1 * rng.normal(size=3), rotational)

    oblique = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    joints = [
        (0, pin.JointModelPrismaticUnaligned(np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0))),
        (1, pin.JointModelRevoluteUnaligned(np.array([0.0, 0.0, -1.0]))),
        (2, pin.JointModelRX()),
        (3, pin.JointModelPY()),
        (2, pin.JointModelRY()),  # second branch off joint 2
        (5, pin.JointModelRevoluteUnaligned(oblique)),
        (6, pin.JointModelPZ()),
        (4, pin.JointModelRZ()),
        (8, pin.JointModelPX()),
    ]
    for k, (parent, jmodel) in enumerate(joints):
        jid = model.addJoint(parent, jmodel, placement(), f"joint{k}")
        model.appendBodyToJoint(jid, inertia(), pin.SE3.Identity())
        model.addJointFrame(jid)
        model.addBodyFrame(f"body{k}", jid, placement(), -1)
    model.addFrame(pin.Frame("tool", len(joints), 0, placement(), pin.FrameType.OP_FRAME))
    model.gravity = pin.Motion(np.array([0.3, -1.0, -9.7]), np.zeros(3))
    model.armature[:] = rng.uniform(0.0, 0.3, model.nv)
    model.lowerPositionLimit[:] = -2.0
    model.upperPositionLimit[:] = 2.0
    return model, "tool"


def _load(name: str) -> tuple[pin.Model, str]:
    if name == HANDMADE:
        return _handmade_model()
    if name in OPTIONAL_ROBOTS:
        pytest.importorskip("example_robot_data")
    from optraj import robots

    robot = robots.load(name)
    assert robot.model.getFrameId(robot.tool_frame) == robot.tool_frame_id
    return robot.model, robot.tool_frame


def _sample_positions(model: pin.Model, rng: np.random.Generator, n: int) -> np.ndarray:
    lower = np.array(model.lowerPositionLimit, dtype=float)
    upper = np.array(model.upperPositionLimit, dtype=float)
    huge = ~np.isfinite(lower) | ~np.isfinite(upper) | (upper - lower > 2.0 * np.pi)
    lower[huge], upper[huge] = -np.pi, np.pi
    return rng.uniform(lower, upper, size=(n, model.nq))


def _intermediate_frame(model: pin.Model, tool_id: int) -> int:
    """A frame on a joint halfway along the tool's chain (not the tool frame itself)."""
    chain = []
    joint = model.frames[tool_id].parentJoint
    while joint > 0:
        chain.append(joint)
        joint = model.parents[joint]
    middle = chain[len(chain) // 2]
    for fid, frame in enumerate(model.frames):
        if frame.parentJoint == middle and fid != tool_id:
            return fid
    raise AssertionError("no intermediate frame found")


@pytest.fixture(scope="module", params=[*ROBOT_NAMES, HANDMADE])
def case(request: pytest.FixtureRequest) -> Case:
    model, tool = _load(request.param)
    rng = np.random.default_rng(SEED)
    tool_id = model.getFrameId(tool)
    return Case(
        name=request.param,
        model=model,
        sym=SymbolicModel(model),
        tool_frame=tool,
        tool_id=tool_id,
        mid_id=_intermediate_frame(model, tool_id),
        qs=_sample_positions(model, rng, N_SAMPLES),
        vs=rng.uniform(-2.0, 2.0, size=(N_SAMPLES, model.nv)),
        accs=rng.uniform(-2.0, 2.0, size=(N_SAMPLES, model.nv)),
    )


def _num(value: ca.DM) -> np.ndarray:
    return np.asarray(value.full(), dtype=float)


def test_frame_pose_matches_pinocchio(case: Case) -> None:
    model, data = case.model, case.model.createData()
    pose = case.sym.frame_pose(case.tool_frame)
    position = case.sym.frame_position(case.tool_frame)
    rotation = case.sym.frame_rotation(case.tool_frame)
    for q in case.qs:
        pin.framesForwardKinematics(model, data, q)
        expected = data.oMf[case.tool_id].homogeneous
        np.testing.assert_allclose(_num(pose(q)), expected, atol=ATOL, rtol=0)
        np.testing.assert_allclose(_num(position(q)).ravel(), expected[:3, 3], atol=ATOL, rtol=0)
        np.testing.assert_allclose(_num(rotation(q)), expected[:3, :3], atol=ATOL, rtol=0)


@pytest.mark.parametrize("which", ["tool", "intermediate"])
def test_frame_jacobian_matches_pinocchio(case: Case, which: str) -> None:
    model, data = case.model, case.model.createData()
    fid = case.tool_id if which == "tool" else case.mid_id
    jacobian = case.sym.frame_jacobian(case.tool_frame if which == "tool" else fid)
    for q in case.qs:
        expected = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
        got = _num(jacobian(q))
        assert got.shape == (6, model.nv)
        np.testing.assert_allclose(got, expected, atol=ATOL, rtol=0)


def test_rnea_matches_pinocchio(case: Case) -> None:
    model, data = case.model, case.model.createData()
    rnea = case.sym.rnea()
    for q, v, a in zip(case.qs, case.vs, case.accs, strict=True):
        expected = pin.rnea(model, data, q, v, a)
        np.testing.assert_allclose(_num(rnea(q, v, a)).ravel(), expected, atol=ATOL, rtol=0)


def test_gravity_torque_matches_pinocchio(case: Case) -> None:
    model, data = case.model, case.model.createData()
    gravity = case.sym.gravity_torque()
    for q in case.qs:
        expected = pin.computeGeneralizedGravity(model, data, q)
        np.testing.assert_allclose(_num(gravity(q)).ravel(), expected, atol=ATOL, rtol=0)


def test_jacobian_linear_rows_match_finite_difference(case: Case) -> None:
    position = case.sym.frame_position(case.tool_frame)
    jacobian = case.sym.frame_jacobian(case.tool_frame)
    steps = FD_STEP * np.eye(case.model.nq)
    for q in case.qs:
        fd = np.column_stack(
            [
                (_num(position(q + e)) - _num(position(q - e))).ravel() / (2.0 * FD_STEP)
                for e in steps
            ]
        )
        np.testing.assert_allclose(_num(jacobian(q))[:3], fd, atol=FD_ATOL, rtol=0)


def test_functions_are_cached_and_named(case: Case) -> None:
    sym = case.sym
    assert sym.frame_jacobian(case.tool_frame) is sym.frame_jacobian(case.tool_id)
    assert sym.rnea() is sym.rnea()
    pose = sym.frame_pose(case.tool_frame)
    assert pose.name().startswith("frame_pose_")
    assert pose.name_in() == ["q"]
    assert sym.rnea().name() == "rnea"
    assert sym.rnea().name_in() == ["q", "v", "a"]
    assert isinstance(sym.rnea().sx_in(0), ca.SX)


def test_pickle_round_trip(case: Case) -> None:
    clone = pickle.loads(pickle.dumps(case.sym))
    q, v, a = case.qs[0], case.vs[0], case.accs[0]
    np.testing.assert_array_equal(_num(clone.rnea()(q, v, a)), _num(case.sym.rnea()(q, v, a)))
    np.testing.assert_array_equal(
        _num(clone.frame_pose(case.tool_frame)(q)), _num(case.sym.frame_pose(case.tool_frame)(q))
    )


def test_unknown_frame_raises(case: Case) -> None:
    with pytest.raises(UnknownNameError, match="not_a_frame") as info:
        case.sym.frame_pose("not_a_frame")
    assert any(frame.name in str(info.value) for frame in case.model.frames)
    with pytest.raises(InvalidInputError):
        case.sym.frame_jacobian(case.model.nframes)


def _model_with(joint: pin.JointModel) -> pin.Model:
    model = pin.Model()
    first = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "ok")
    model.addJoint(first, joint, pin.SE3.Identity(), "bad")
    return model


@pytest.mark.parametrize(
    "joint_factory",
    [
        pin.JointModelSpherical,
        pin.JointModelFreeFlyer,
        pin.JointModelRUBX,  # continuous joint: nq = 2
        pin.JointModelPlanar,
        lambda: pin.JointModelHZ(0.01),
    ],
    ids=["spherical", "free_flyer", "continuous", "planar", "helical"],
)
def test_unsupported_joint_raises(joint_factory: Callable[[], pin.JointModel]) -> None:
    model = _model_with(joint_factory())
    with pytest.raises(UnsupportedModelError, match="bad"):
        SymbolicModel(model)


def test_mimic_joint_raises() -> None:
    model = pin.buildModelFromXML(MIMIC_URDF, mimic=True)
    with pytest.raises(UnsupportedModelError, match="j2"):
        SymbolicModel(model)


def test_accepts_a_robot_and_rejects_other_objects() -> None:
    robot = robots.load("paddle4")
    sym = SymbolicModel(robot)
    q = robot.home
    np.testing.assert_allclose(
        _num(sym.frame_pose(robot.tool_frame)(q)), robot.tool_pose(q), atol=1e-12
    )
    with pytest.raises(InvalidInputError, match=r"robots\.Robot or a pinocchio\.Model"):
        SymbolicModel(None)  # type: ignore[arg-type]


def test_functions_can_be_requested_from_many_threads() -> None:
    sym = SymbolicModel(robots.load("sawyer"))
    frames = [f.name for f in sym.model.frames][1:]

    def build(offset: int) -> None:
        for name in frames[offset:] + frames[:offset]:
            sym.frame_pose(name)(np.zeros(sym.nq))

    assert race(build, 6) == []
