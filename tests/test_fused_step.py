"""The fused QP step against the pieces it replaces (controllers.qp_terms via DiffIKQP.build)."""

from __future__ import annotations

import dataclasses
import pickle
import shutil

import numpy as np
import pytest
from conftest import get_robot

import controllers
import planners
import problems
from controllers.controller import Reference, State
from controllers.diff_ik_qp import DiffIKQP, _ActiveSet
from controllers.fused_step import FusedStep, StepSettings
from controllers.simulation import Noise, simulate
from optraj.errors import CompilerError, UnknownNameError

DT = 1e-3
HAS_GCC = shutil.which("gcc") is not None


def _fused(controller: DiffIKQP, compiled: bool = False) -> FusedStep:
    return (
        controller._make_fused()
        if not compiled
        else FusedStep(controller.robot, _settings(controller), compiled=True)
    )


def _settings(controller: DiffIKQP) -> StepSettings:
    return StepSettings(
        controller.pid,
        controller.weights,
        controller.damping,
        controller.posture_weight,
        controller.posture_gain,
        controller.limits,
        controller.velocity_scale,
        controller.position_gain,
        _ActiveSet.SLACK,
        controller.active_set_changes,
    )


def _random_step(robot, rng, spread=0.01):
    """A state, a reference near it, an integral and a last command near the state's speed."""
    limits = robot.limits
    middle = (limits.lower + limits.upper) / 2
    half = (limits.upper - limits.lower) / 2
    q = middle + rng.uniform(-0.98, 0.98, robot.dof) * half  # some joints near a limit
    qd = rng.uniform(-0.5, 0.5, robot.dof) * limits.velocity
    q_ref = q + rng.normal(0.0, spread, robot.dof)
    T = robot.tool_pose(q_ref)
    twist = robot.jacobian(q_ref) @ rng.uniform(-0.3, 0.3, robot.dof)
    reference = Reference(0.0, q_ref, qd, np.zeros(robot.dof), T, twist, "")
    last = qd + rng.normal(0.0, 1e-3, robot.dof) * limits.acceleration
    integral = rng.uniform(-0.5, 0.5, 6) * np.repeat([0.01, 0.05], 3)
    return State(0.0, q, qd), reference, last, integral


@pytest.mark.parametrize(
    ("name", "settings"),
    [
        ("sawyer", {}),
        ("sawyer", {"task": "axis"}),
        ("sawyer", {"kd": 0.2, "posture_weight": 0.0, "weights": (1.0, 0.3)}),
        ("paddle4", {"velocity_scale": 0.7}),
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
        controller._last = last
        controller.pid._integral = integral.copy()
        qp = controller.build(state, reference, DT)  # advances the PID's integral
        # The QP's own active set (by the search) half the time, else one joint toggled.
        found = None if qp.relaxed else _ActiveSet.none(robot.dof).search(qp, 20)
        upper, lower = (found[0].upper, found[0].lower) if found else (held, held)
        upper, lower = upper.copy(), lower.copy()
        if found is None or rng.random() < 0.5:
            j = rng.integers(robot.dof)
            upper[j], lower[j] = (False, False) if upper[j] or lower[j] else (True, False)
        fused.set_active(upper, lower)
        ok, fallback = fused(
            state.q, state.qd, reference.T_world_tool, reference.twist, reference.q,
            integral, last, DT,
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
        active = _ActiveSet(upper, lower)
        x = active._on_bounds(qp)
        np.testing.assert_allclose(fused.x, x, rtol=0, atol=1e-9 * max(1.0, np.abs(x).max()))
        optimal = active._next(qp, x) is active
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
        controller._last = last
        controller.pid._integral = integral.copy()
        qp = controller.build(state, reference, DT)
        fused.set_active(np.zeros(robot.dof, bool), np.zeros(robot.dof, bool))
        _, fallback = fused(
            q, state.qd, reference.T_world_tool, reference.twist, reference.q, integral,
            last, DT,
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
            state.q, state.qd, T_ref, reference.twist, reference.q, integral, last, DT
        )
        assert fallback == expected, angle


def _closed_loop(controller, trajectory, **options):
    return simulate(controller.robot, trajectory, controller, plant="kinematic", **options)


@pytest.fixture(scope="module")
def strikes():
    shot = problems.sawyer_pool_shot(speed=1.0)
    planner = planners.OptimalControl("time")
    nominal = planner.plan(dataclasses.replace(shot, limits=shot.robot.limits.scaled(0.8)))
    return shot.robot, {"nominal": nominal, "at the limits": planner.plan(shot)}


@pytest.mark.parametrize("case", ["nominal", "at the limits", "noisy", "axis task"])
def test_closed_loop_commands_equal_the_pieces(strikes, case):
    robot, planned = strikes
    trajectory = planned["nominal" if case != "at the limits" else "at the limits"]
    options = {"noise": Noise(seed=7)} if case == "noisy" else {}
    settings = {"task": "axis"} if case == "axis task" else {}
    runs = {
        evaluation: _closed_loop(
            DiffIKQP(robot, evaluation=evaluation, **settings), trajectory, **options
        )
        for evaluation in ("pieces", "fused")
    }
    np.testing.assert_allclose(runs["fused"].command, runs["pieces"].command, rtol=0, atol=1e-9)
    # The run exercises the limits where it should: commands on a velocity bound.
    if case == "at the limits":
        on_bound = np.isclose(np.abs(runs["fused"].command), robot.limits.velocity, rtol=1e-9)
        assert on_bound.sum() > 10
    assert runs["fused"].metrics.violations["command"].count == 0


def test_a_changed_active_set_is_solved_by_the_search_and_osqp():
    """Where the last active set no longer holds, the fused numbers go to the search."""
    robot = get_robot("sawyer")
    rng = np.random.default_rng(43)
    fused, pieces = DiffIKQP(robot), DiffIKQP(robot, evaluation="pieces")
    paths = set()
    for _ in range(60):
        state, reference, last, integral = _random_step(robot, rng)
        for controller in (fused, pieces):
            controller.reset(state)
            controller._last = last.copy()
            controller.pid._integral = integral.copy()
        a = fused.step(state, reference, DT)
        b = pieces.step(state, reference, DT)
        np.testing.assert_allclose(a.qd, b.qd, rtol=0, atol=1e-9)
        assert fused.diagnostics["solver"] == pieces.diagnostics["solver"]
        assert fused.diagnostics["relaxed"] == pieces.diagnostics["relaxed"]
        paths.add((fused.diagnostics["solver"], bool(fused.diagnostics["relaxed"])))
    # Steps of every kind: kept at once or after changes, and relaxed boxes via the pieces.
    assert ("active set", False) in paths
    assert ("active set", True) in paths


def test_pickled_fused_controller_rebuilds_its_function():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(44)
    controller = DiffIKQP(robot)
    state, reference, _, _ = _random_step(robot, rng)
    controller.reset(state)
    controller.step(state, reference, DT)
    clone = pickle.loads(pickle.dumps(controller))
    assert clone._fused is None
    np.testing.assert_array_equal(
        clone.step(state, reference, DT).qd, controller.step(state, reference, DT).qd
    )
    with pytest.raises(TypeError, match="rebuild"):
        pickle.dumps(controller._fused)


@pytest.mark.skipif(not HAS_GCC, reason="no C compiler (gcc) on this machine")
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
    with pytest.raises(CompilerError, match="no-such-cc"):
        FusedStep(robot, _settings(controller), compiled=True, compiler="no-such-cc")
    with pytest.raises(UnknownNameError, match="evaluation 'fast'"):
        DiffIKQP(robot, evaluation="fast")  # type: ignore[arg-type]


def test_extra_rows_use_the_pieces():
    robot = get_robot("paddle4")
    rows = controllers.Constraint(np.ones((1, robot.dof)), np.array([-0.1]), np.array([0.1]))
    controller = DiffIKQP(robot, constraints=[rows])
    assert controller._fused is None
