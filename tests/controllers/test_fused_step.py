"""The fused QP step against the pieces it replaces (controllers.qp_terms via DiffIKQP.build)."""

from __future__ import annotations

import dataclasses
import pickle
import shutil

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from optraj import controllers, planners, problems, robots
from optraj.controllers.active_set import ActiveSet
from optraj.controllers.controller import Reference, State
from optraj.controllers.diff_ik_qp import DiffIKQP
from optraj.controllers.fused_step import FusedStep, solve_on_set
from optraj.controllers.qp_terms import QP, identity
from optraj.controllers.simulation import Noise, simulate
from optraj.errors import CompilerError, UnknownNameError, UnsupportedModelError

DT = 1e-3
HAS_GCC = shutil.which("gcc") is not None


def _fused(controller: DiffIKQP) -> FusedStep:
    return FusedStep(controller.robot, controller.step_settings())


def _start(controller: DiffIKQP, state: State, last, integral) -> None:
    """Reset the controller to continue from this last command and PID integral."""
    controller.reset(State(state.t, state.q, last))
    controller.pid.reset(integral)


def _random_step(robot, rng, spread=0.01):
    """A state, a reference near it, an integral and a last command near the state's speed."""
    limits = robot.limits
    middle = (limits.lower + limits.upper) / 2
    half = (limits.upper - limits.lower) / 2
    q = middle + rng.uniform(-0.98, 0.98, robot.dof) * half  # some joints near a limit
    qd = rng.uniform(-0.5, 0.5, robot.dof) * limits.velocity
    q_ref = q + rng.normal(0.0, spread, robot.dof)
    qd_ref = rng.uniform(-0.3, 0.3, robot.dof) * limits.velocity
    T = robot.tool_pose(q_ref)
    twist = robot.jacobian(q_ref) @ qd_ref
    reference = Reference(0.0, q_ref, qd_ref, np.zeros(robot.dof), T, twist, "")
    last = qd + rng.normal(0.0, 1e-3, robot.dof) * limits.acceleration
    integral = rng.uniform(-0.5, 0.5, 6) * np.repeat([0.01, 0.05], 3)
    return State(0.0, q, qd), reference, last, integral


@pytest.mark.parametrize(
    ("name", "settings"),
    [
        ("sawyer", {}),
        ("sawyer", {"task": "axis"}),
        ("sawyer", {"kd": 0.2, "posture_weight": 0.0, "weights": (1.0, 0.3)}),
        ("sawyer", {"ki": 0.0, "active_set_changes": 2}),
        ("sawyer", {"posture_velocity": False}),
        ("paddle4", {"velocity_scale": 0.7}),
        ("paddle4", {"posture_velocity": False, "task": "axis"}),
    ],
)
def test_numbers_and_optimality_test_equal_the_pieces(name, settings):
    robot = get_robot(name)
    rng = np.random.default_rng(41)
    controller = DiffIKQP(robot, **settings)
    fused = _fused(controller)
    compared = accepted = refused = searched = 0
    held = np.zeros(robot.dof, dtype=bool)
    for _ in range(300):
        state, reference, last, integral = _random_step(robot, rng)
        _start(controller, state, last, integral)
        qp = controller.build(state, reference, DT)  # advances the PID's integral
        # The QP's own active set (by the search) half the time, else one joint toggled.
        found = None if qp.relaxed else ActiveSet.none(robot.dof).search(qp, 20)
        upper, lower = (found[0].upper, found[0].lower) if found else (held, held)
        upper, lower = upper.copy(), lower.copy()
        if found is None or rng.random() < 0.5:
            j = rng.integers(robot.dof)
            upper[j], lower[j] = (False, False) if upper[j] or lower[j] else (True, False)
        fused.set_active(upper, lower)
        ok, fallback = fused(
            state.q, state.qd, reference.T_world_tool, reference.twist, reference.q,
            reference.qd if controller.posture_velocity else np.zeros(robot.dof), integral,
            last, DT,
        )  # fmt: skip
        assert fallback == bool(qp.relaxed)
        if fallback:
            continue
        compared += 1
        scale = max(1.0, float(np.abs(qp.H).max()))
        np.testing.assert_allclose(fused.H, qp.H, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(fused.c, qp.c, rtol=0, atol=1e-12 * scale)
        np.testing.assert_array_equal(fused.lower, qp.lower)
        np.testing.assert_array_equal(fused.upper, qp.upper)
        np.testing.assert_allclose(fused.integral, controller.pid.integral, rtol=0, atol=1e-15)
        active = ActiveSet(upper, lower)
        x = active.on_bounds(qp)
        np.testing.assert_allclose(fused.x, x, rtol=0, atol=1e-9 * max(1.0, np.abs(x).max()))
        optimal = active.next_set(qp, x) is active
        assert ok == optimal
        accepted += optimal
        refused += not optimal
        if not optimal:  # the further rounds reach the set the NumPy search reaches
            found = active.search(qp, controller.active_set_changes + 1)
            assert fused.search() == (found is not None)
            if found is not None:
                searched += 1
                np.testing.assert_array_equal(fused.searched_upper > 0.5, found[0].upper)
                np.testing.assert_array_equal(fused.searched_lower > 0.5, found[0].lower)
                np.testing.assert_allclose(fused.searched_x, found[1], rtol=0, atol=1e-9)
    # Both outcomes of the optimality test and of the box overlap occur.
    assert compared > 100
    assert accepted > 10
    assert refused > 10
    assert searched > 10


@pytest.mark.parametrize("name", ["sawyer", "paddle4"])
def test_the_posture_velocity_input_enters_c_as_in_the_pieces(name):
    # The same step with and without the planned joint velocity in the posture term: only c
    # moves, by -w qd_ref, in the fused step as in the pieces.
    robot = get_robot(name)
    rng = np.random.default_rng(49)
    controller = DiffIKQP(robot, evaluation="pieces")
    fused = _fused(controller)
    resting = DiffIKQP(robot, evaluation="pieces", posture_velocity=False)
    none = np.zeros(robot.dof, dtype=bool)
    for _ in range(50):
        state, reference, last, integral = _random_step(robot, rng)
        outputs = []
        for qd_ref in (reference.qd, np.zeros(robot.dof)):
            fused.set_active(none, none)
            fused(
                state.q, state.qd, reference.T_world_tool, reference.twist, reference.q,
                qd_ref, integral, last, DT,
            )  # fmt: skip
            outputs.append((fused.H.copy(), fused.c.copy()))
        (H_moving, c_moving), (H_resting, c_resting) = outputs
        np.testing.assert_array_equal(H_moving, H_resting)
        np.testing.assert_allclose(
            c_moving - c_resting, -controller.posture_weight * reference.qd, rtol=0, atol=1e-12
        )
        for pieces, c in ((controller, c_moving), (resting, c_resting)):
            _start(pieces, state, last, integral)
            qp = pieces.build(state, reference, DT)
            scale = max(1.0, float(np.abs(qp.H).max()))
            np.testing.assert_allclose(c, qp.c, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("side", ["upper", "lower"])
def test_a_joint_beyond_its_position_limit_is_sent_back_as_by_the_pieces(side):
    robot = get_robot("sawyer")
    controller = DiffIKQP(robot)
    fused = _fused(controller)
    rng = np.random.default_rng(45)
    compared = 0
    for j in range(robot.dof):
        state, reference, _, integral = _random_step(robot, rng, spread=0.0)
        q = state.q.copy()
        sign = 1.0 if side == "upper" else -1.0
        q[j] = (robot.limits.upper if side == "upper" else robot.limits.lower)[j] + sign * 1e-4
        state = State(0.0, q, np.zeros(robot.dof))
        # Already moving back at the speed the position bound asks for.
        last = np.zeros(robot.dof)
        last[j] = -sign * controller.position_gain * 1e-4 / DT
        _start(controller, state, last, integral)
        qp = controller.build(state, reference, DT)
        fused.set_active(np.zeros(robot.dof, bool), np.zeros(robot.dof, bool))
        _, fallback = fused(
            q, state.qd, reference.T_world_tool, reference.twist, reference.q, reference.qd,
            integral, last, DT,
        )  # fmt: skip
        assert fallback == bool(qp.relaxed)
        if not fallback:
            compared += 1
            np.testing.assert_array_equal(fused.lower, qp.lower)
            np.testing.assert_array_equal(fused.upper, qp.upper)
            back = qp.upper[j] if side == "upper" else -qp.lower[j]
            assert back < 0.0  # the joint must move back inside
    assert compared >= robot.dof - 1


def test_a_rotation_error_near_half_a_turn_goes_to_the_pieces():
    robot = get_robot("sawyer")
    controller = DiffIKQP(robot)
    fused = _fused(controller)
    rng = np.random.default_rng(42)
    state, reference, last, integral = _random_step(robot, rng, spread=0.0)
    flip = np.diag([1.0, -1.0, -1.0, 1.0])  # half a turn about the tool x axis
    for angle, expected in ((np.pi - 2e-3, False), (np.pi - 5e-4, True), (np.pi, True)):
        turn = np.eye(4)
        turn[1:3, 1:3] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
        T_ref = reference.T_world_tool @ (turn if angle < np.pi else flip)
        _, fallback = fused(
            state.q, state.qd, T_ref, reference.twist, reference.q, reference.qd, integral,
            last, DT,
        )  # fmt: skip
        assert fallback == expected, angle


def test_a_step_near_half_a_turn_is_the_pieces_step_with_one_integral_advance():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(47)
    state, reference, _, integral = _random_step(robot, rng, spread=0.0)
    flipped = reference._replace(T_world_tool=reference.T_world_tool @ np.diag([1, -1, -1, 1.0]))
    fused, pieces = DiffIKQP(robot), DiffIKQP(robot, evaluation="pieces")
    for controller in (fused, pieces):
        _start(controller, state, state.qd, integral)
    a, b = fused.step(state, flipped, DT), pieces.step(state, flipped, DT)
    assert fused.diagnostics["evaluation"] == "pieces"
    np.testing.assert_array_equal(a.qd, b.qd)
    np.testing.assert_array_equal(fused.pid.integral, pieces.pid.integral)
    assert not np.array_equal(fused.pid.integral, integral)  # advanced, once


def test_one_round_equals_the_numpy_round_with_pinned_joints():
    n = 7
    H, c, lower, upper, held_upper, held_lower = (
        ca.SX.sym(name, *shape)
        for name, shape in (
            ("H", (n, n)), ("c", (n, 1)), ("lower", (n, 1)), ("upper", (n, 1)),
            ("held_upper", (n, 1)), ("held_lower", (n, 1)),
        )
    )  # fmt: skip
    round_ = ca.Function(
        "round",
        [H, c, lower, upper, held_upper, held_lower],
        list(solve_on_set(H, c, lower, upper, held_upper, held_lower, ActiveSet.SLACK)),
    )
    rng = np.random.default_rng(48)
    kinds = {"optimal": 0, "changed": 0, "pinned held at lower": 0}
    for _ in range(400):
        root = rng.normal(size=(n, n))
        Hn = root @ root.T + 1e-3 * np.eye(n)
        cn = rng.normal(size=n)
        middle = rng.normal(size=n)
        width = rng.uniform(0.0, 1.0, n) * (rng.random(n) < 0.8)  # some bounds meet
        lo, up = middle - width, middle + width
        qp = QP(Hn, cn, identity(n), lo, up, ())
        found = ActiveSet.none(n).search(qp, 60)
        if found is None:
            continue
        up_mask, lo_mask = found[0].upper.copy(), found[0].lower.copy()
        pinned = (lo >= up) & up_mask
        if rng.random() < 0.5:  # pinned joints held at their lower bound instead
            up_mask &= ~pinned
            lo_mask |= pinned
        if rng.random() < 0.4:  # a wrong guess
            toggle = rng.integers(n)
            up_mask[toggle], lo_mask[toggle] = (
                lo_mask[toggle],
                not (up_mask[toggle] | lo_mask[toggle]),
            )
        active = ActiveSet(up_mask, lo_mask)
        x = active.on_bounds(qp)
        following = active.next_set(qp, x)
        xf, ok, next_upper, next_lower = (
            np.asarray(v).ravel() for v in round_(Hn, cn, lo, up, up_mask, lo_mask)
        )
        np.testing.assert_allclose(xf, x, rtol=0, atol=1e-8 * max(1.0, np.abs(x).max()))
        assert bool(ok[0]) == (following is active)
        if following is active:
            kinds["optimal"] += 1
            kinds["pinned held at lower"] += bool((lo_mask & (lo >= up)).any())
            expected = (up_mask, lo_mask)  # kept as it is
        else:
            kinds["changed"] += 1
            expected = (following.upper, following.lower)
        np.testing.assert_array_equal(next_upper > 0.5, expected[0])
        np.testing.assert_array_equal(next_lower > 0.5, expected[1])
    assert min(kinds.values()) > 10, kinds


def _closed_loop(controller, trajectory, **options):
    return simulate(controller.robot, trajectory, controller, **({"plant": "kinematic"} | options))


@pytest.fixture(scope="module")
def strikes():
    shot = problems.sawyer_pool_shot(speed=1.0)
    planner = planners.OptimalControl("time")
    nominal = planner.plan(dataclasses.replace(shot, limits=shot.robot.limits.scaled(0.8)))
    return shot.robot, {"nominal": nominal, "at the limits": planner.plan(shot)}


@pytest.mark.parametrize(
    "case", ["nominal", "at the limits", "noisy", "axis task", "posture at rest", "dynamic"]
)
def test_closed_loop_commands_equal_the_pieces(strikes, case):
    robot, planned = strikes
    trajectory = planned["nominal" if case != "at the limits" else "at the limits"]
    options: dict[str, object] = {"noise": Noise(seed=7)} if case == "noisy" else {}
    if case == "dynamic":  # the feed-forward torque reaches the plant
        options["plant"] = "dynamic"
    settings = {
        "axis task": {"task": "axis"},
        "posture at rest": {"posture_velocity": False, "feedforward": False},
    }.get(case, {})
    runs = {
        evaluation: _closed_loop(
            DiffIKQP(robot, evaluation=evaluation, **settings), trajectory, **options
        )
        for evaluation in ("pieces", "fused")
    }
    # A closed loop carries the round-off of the two evaluation orders forward (noise makes
    # every step different): 7e-8 rad/s at most over the 1.9 s noisy run.
    np.testing.assert_allclose(runs["fused"].command, runs["pieces"].command, rtol=0, atol=1e-6)
    # The run exercises the limits where it should: commands on a velocity bound.
    if case == "at the limits":
        on_bound = np.isclose(np.abs(runs["fused"].command), robot.limits.velocity, rtol=1e-9)
        assert on_bound.sum() > 10
    assert runs["fused"].metrics.violations["command"].count == 0


def test_steps_from_random_states_take_the_pieces_paths():
    """From the empty set: kept at once or after changes, OSQP, and relaxed boxes."""
    robot = get_robot("sawyer")
    rng = np.random.default_rng(43)
    fused, pieces = DiffIKQP(robot), DiffIKQP(robot, evaluation="pieces")
    paths = set()
    for _ in range(60):
        state, reference, last, integral = _random_step(robot, rng)
        for controller in (fused, pieces):
            _start(controller, state, last, integral)
        a = fused.step(state, reference, DT)
        b = pieces.step(state, reference, DT)
        np.testing.assert_allclose(a.qd, b.qd, rtol=0, atol=1e-9)
        assert fused.diagnostics["solver"] == pieces.diagnostics["solver"]
        assert fused.diagnostics["relaxed"] == pieces.diagnostics["relaxed"]
        assert pieces.diagnostics["evaluation"] == "pieces"
        relaxed = bool(fused.diagnostics["relaxed"])
        assert fused.diagnostics["evaluation"] == ("pieces" if relaxed else "fused")
        paths.add((fused.diagnostics["solver"], relaxed))
    # Steps of every kind: the active set, OSQP, and relaxed boxes via the pieces.
    assert ("active set", False) in paths
    assert ("osqp", False) in paths
    assert ("active set", True) in paths


def test_every_call_solves_on_the_controllers_active_set(monkeypatch):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(46)
    controller = DiffIKQP(robot)
    original = FusedStep.__call__
    calls = []

    def checked(self, *args):
        held = self.active > 0.5
        np.testing.assert_array_equal(held[: robot.dof], controller.active_set.upper)
        np.testing.assert_array_equal(held[robot.dof :], controller.active_set.lower)
        calls.append(controller.active_set.empty)
        return original(self, *args)

    monkeypatch.setattr(FusedStep, "__call__", checked)
    state, reference, _, _ = _random_step(robot, rng)
    controller.reset(state)
    for _ in range(200):
        command = controller.step(state, reference, DT)
        q = state.q + command.qd * DT + rng.normal(0.0, 2e-4, robot.dof)
        state = State(state.t + DT, q, command.qd)
    assert len(calls) == 200
    assert calls.count(False) > 20  # most steps start from a set that holds bounds


def test_pickled_fused_controller_rebuilds_its_function():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(44)
    controller = DiffIKQP(robot)
    state, reference, _, _ = _random_step(robot, rng)
    controller.reset(state)
    controller.step(state, reference, DT)
    # A FusedStep refuses to pickle, so the controller pickles without its function ...
    with pytest.raises(TypeError, match="rebuild"):
        pickle.dumps(_fused(controller))
    clone = pickle.loads(pickle.dumps(controller))
    # ... and the clone rebuilds it for its next step.
    np.testing.assert_array_equal(
        clone.step(state, reference, DT).qd, controller.step(state, reference, DT).qd
    )
    assert clone.diagnostics["evaluation"] == "fused"


@pytest.mark.skipif(not HAS_GCC, reason="no C compiler (gcc) on this machine")
@pytest.mark.slow
def test_compiled_step_equals_the_virtual_machine(strikes):
    robot, planned = strikes
    runs = [
        _closed_loop(DiffIKQP(robot, evaluation=e), planned["at the limits"])
        for e in ("fused", "compiled")
    ]
    np.testing.assert_allclose(runs[1].command, runs[0].command, rtol=0, atol=1e-12)


def test_a_missing_compiler_and_an_unknown_evaluation_are_named():
    robot = get_robot("paddle4")
    controller = DiffIKQP(robot)
    with pytest.raises(CompilerError, match=r"could not compile .* with 'no-such-cc'"):
        FusedStep(robot, controller.step_settings(), compiled=True, compiler="no-such-cc")
    with pytest.raises(UnknownNameError, match="evaluation 'fast'"):
        DiffIKQP(robot, evaluation="fast")  # type: ignore[arg-type]


def test_extra_rows_use_the_pieces():
    robot = get_robot("paddle4")
    rows = controllers.Constraint(np.ones((1, robot.dof)), np.array([-0.1]), np.array([0.1]))
    controller = DiffIKQP(robot, constraints=[rows])
    q = robot.home
    reference = Reference(0.0, q, np.zeros(robot.dof), np.zeros(robot.dof), robot.tool_pose(q),
                          np.zeros(6), "")  # fmt: skip
    controller.reset(State(0.0, q, np.zeros(robot.dof)))
    controller.step(State(0.0, q, np.zeros(robot.dof)), reference, DT)
    assert controller.evaluation == "fused"  # as asked, but the extra rows need the pieces
    assert controller.diagnostics["evaluation"] == "pieces"


def _helical_robot():
    """Two joints, the second helical: Pinocchio handles it, robots.SymbolicModel does not."""
    model = pin.Model()
    first = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "turn")
    offset = pin.SE3(np.eye(3), np.array([0.3, 0.0, 0.0]))
    second = model.addJoint(first, pin.JointModelHZ(0.01), offset, "screw")
    model.appendBodyToJoint(first, pin.Inertia.FromSphere(1.0, 0.05), pin.SE3.Identity())
    model.appendBodyToJoint(second, pin.Inertia.FromSphere(1.0, 0.05), pin.SE3.Identity())
    tool = pin.SE3(np.eye(3), np.array([0.2, 0.0, 0.0]))
    model.addFrame(pin.Frame("tool", second, 0, tool, pin.FrameType.OP_FRAME))
    limits = robots.JointLimits(
        names=("turn", "screw"),
        kinds=("rad", "rad"),
        lower=[-3.0, -3.0],
        upper=[3.0, 3.0],
        velocity=[2.0, 2.0],
        acceleration=[10.0, 10.0],
        jerk=[100.0, 100.0],
        effort=[50.0, 50.0],
    )
    return robots.Robot("helical", model, limits, "tool", {"home": [0.0, 0.0]})


def test_joints_the_symbolic_model_lacks_leave_the_default_on_the_pieces():
    robot = _helical_robot()
    controller = DiffIKQP(robot, task="axis")
    assert controller.evaluation == "pieces"
    q = np.array([0.2, -0.4])
    reference = Reference(0.0, q + 0.01, np.zeros(2), np.zeros(2), robot.tool_pose(q + 0.01),
                          np.zeros(6), "")  # fmt: skip
    controller.reset(State(0.0, q, np.zeros(2)))
    command = controller.step(State(0.0, q, np.zeros(2)), reference, DT)
    assert controller.diagnostics["evaluation"] == "pieces"
    assert np.all(np.abs(command.qd) <= robot.limits.velocity)
    with pytest.raises(UnsupportedModelError, match="screw"):
        DiffIKQP(robot, evaluation="compiled")
