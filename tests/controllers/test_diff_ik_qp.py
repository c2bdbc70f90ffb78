from __future__ import annotations

import pickle

import numpy as np
import pytest
from conftest import get_robot
from scipy.optimize import lsq_linear

from optraj.controllers import diff_ik_qp
from optraj.controllers.active_set import ActiveSet
from optraj.controllers.controller import Reference, State
from optraj.controllers.diff_ik_qp import DiffIKQP
from optraj.controllers.osqp_workspace import OSQPWorkspace
from optraj.controllers.qp_terms import Constraint, task_weights
from optraj.errors import InvalidInputError, UnknownNameError

DT = 1e-3


def _reference(robot, q_ref, qd_ref) -> Reference:
    T = robot.tool_pose(q_ref)
    twist = robot.jacobian(q_ref) @ qd_ref
    return Reference(0.0, q_ref, qd_ref, np.zeros_like(q_ref), T, twist, "")


def _random_case(robot, rng):
    """A configuration, a reference near it moving at a modest speed."""
    limits = robot.limits
    middle = (limits.lower + limits.upper) / 2
    half = (limits.upper - limits.lower) / 2
    q = middle + rng.uniform(-0.6, 0.6, robot.dof) * half
    q_ref = q + rng.normal(0.0, 0.002, robot.dof)
    qd_ref = rng.uniform(-0.2, 0.2, robot.dof) * limits.velocity
    return q, _reference(robot, q_ref, qd_ref)


def _stacked_least_squares(robot, controller, q, reference):
    """The QP's objective as one least-squares system, built from the robot directly."""
    J = robot.jacobian(q)
    T = robot.tool_pose(q)
    v = controller.pid.twist(T, J, np.zeros(robot.dof), reference, DT)
    axis = T[:3, 2] if controller.pid.task == "axis" else None
    W = task_weights(*controller.weights, axis=axis)
    root = np.linalg.cholesky(W + 1e-300 * np.eye(6)) if axis is None else _sqrt_psd(W)
    rows = [root.T @ J, np.sqrt(controller.damping) * np.eye(robot.dof)]
    rhs = [root.T @ v, np.zeros(robot.dof)]
    if controller.posture_weight > 0:
        target = controller.posture_gain * (reference.q - q)
        if controller.posture_velocity:
            target = target + reference.qd
        rows.append(np.sqrt(controller.posture_weight) * np.eye(robot.dof))
        rhs.append(np.sqrt(controller.posture_weight) * target)
    return np.vstack(rows), np.concatenate(rhs)


def _sqrt_psd(W):
    values, vectors = np.linalg.eigh(W)
    return vectors @ np.diag(np.sqrt(np.clip(values, 0.0, None))) @ vectors.T


@pytest.mark.parametrize("posture_velocity", [True, False])
@pytest.mark.parametrize(
    ("name", "task"), [("sawyer", "pose"), ("sawyer", "axis"), ("paddle4", "pose")]
)
def test_unconstrained_solution_equals_least_squares(name, task, posture_velocity):
    robot = get_robot(name)
    rng = np.random.default_rng(11)
    for _ in range(20):
        controller = DiffIKQP(robot, ki=0.0, task=task, posture_velocity=posture_velocity)
        q, reference = _random_case(robot, rng)
        A, b = _stacked_least_squares(robot, controller, q, reference)
        expected = np.linalg.lstsq(A, b, rcond=None)[0]
        state = State(0.0, q, expected)  # the acceleration bound is centred on this velocity
        controller.reset(state)
        qp = controller.build(state, reference, DT)
        assert np.all(expected > qp.lower + 1e-6) and np.all(expected < qp.upper - 1e-6)
        controller.reset(state)
        command = controller.step(state, reference, DT)
        assert command.status == "ok"
        np.testing.assert_allclose(command.qd, expected, atol=1e-6, rtol=0)


@pytest.mark.slow
def test_constrained_solution_equals_bounded_least_squares():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(12)
    active_cases = 0
    for _ in range(15):
        controller = DiffIKQP(robot, ki=0.0, velocity_scale=0.05, kp=200.0)
        q, reference = _random_case(robot, rng)
        state = State(0.0, q, np.zeros(robot.dof))
        controller.reset(state)  # the last command: the state's (zero) velocity
        qp = controller.build(state, reference, DT)
        A, b = _stacked_least_squares(robot, controller, q, reference)
        expected = lsq_linear(A, b, bounds=(qp.lower, qp.upper), tol=1e-14, method="bvls").x
        controller.reset(state)
        command = controller.step(state, reference, DT)
        np.testing.assert_allclose(command.qd, expected, atol=1e-6, rtol=0)
        active_cases += np.any(np.isclose(expected, qp.upper) | np.isclose(expected, qp.lower))
    assert active_cases >= 10  # the test exercises bounds that bind


@pytest.mark.parametrize("changes", [0, diff_ik_qp.ACTIVE_SET_CHANGES])
def test_active_set_path_gives_the_exact_solution_as_the_active_set_changes(changes):
    # A closed loop whose references jump now and then: most steps keep the last active set
    # (solved by one linear solve), the jumps change it (a few active-set changes, or OSQP
    # when none are allowed). Every command must equal the bounded least-squares solution of
    # its step's QP, whichever path produced it.
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(22)
    controller = DiffIKQP(robot, ki=0.0, kp=300.0, active_set_changes=changes)
    q, reference = _random_case(robot, rng)
    last = np.zeros(robot.dof)
    controller.reset(State(0.0, q, last))
    paths = {"active set": 0, "osqp": 0}
    held = 0
    for k in range(150):
        if k % 10 == 0:
            q_ref = np.clip(q + rng.normal(0.0, 0.05, robot.dof), limits.lower, limits.upper)
            reference = _reference(
                robot, q_ref, rng.uniform(-0.5, 0.5, robot.dof) * limits.velocity
            )
        state = State(k * DT, q, last)
        qp = controller.build(state, reference, DT)  # ki = 0: building twice changes nothing
        A, b = _stacked_least_squares(robot, controller, q, reference)
        expected = lsq_linear(A, b, bounds=(qp.lower, qp.upper), tol=1e-14, method="bvls").x
        command = controller.step(state, reference, DT)
        assert command.status == "ok"
        np.testing.assert_allclose(command.qd, expected, atol=1e-6, rtol=0)
        paths[controller.diagnostics["solver"]] += 1
        held += bool(np.any(np.isclose(command.qd, qp.upper) | np.isclose(command.qd, qp.lower)))
        q = q + command.qd * DT
        last = command.qd
    if changes == 0:
        assert paths["active set"] >= 100 and paths["osqp"] >= 10, paths
    else:  # the changes the jumps need are found without OSQP
        assert paths["osqp"] <= 2, paths
    assert held >= 50  # bounds bind on many steps, not only the unconstrained case


def test_a_wrong_active_set_guess_is_refused_and_osqp_decides():
    robot = get_robot("sawyer")
    n = robot.dof
    rng = np.random.default_rng(23)
    q, reference = _random_case(robot, rng)
    A, b = _stacked_least_squares(robot, DiffIKQP(robot, ki=0.0), q, reference)
    unconstrained = np.linalg.lstsq(A, b, rcond=None)[0]
    # A velocity limit just below the fastest joint's need: some bounds bind, some joints not.
    scale = 0.95 * float(np.max(np.abs(unconstrained) / robot.limits.velocity))
    limit = scale * robot.limits.velocity
    controller = DiffIKQP(robot, ki=0.0, velocity_scale=scale, active_set_changes=0)
    state = State(0.0, q, np.clip(unconstrained, -limit, limit))
    controller.reset(state)
    qp = controller.build(state, reference, DT)
    expected = lsq_linear(A, b, bounds=(qp.lower, qp.upper), tol=1e-14, method="bvls").x
    at_upper = np.isclose(expected, qp.upper, atol=1e-9)
    at_lower = np.isclose(expected, qp.lower, atol=1e-9)
    free = ~(at_upper | at_lower)
    assert at_upper.any() and free.any()
    right = ActiveSet(at_upper, at_lower)
    np.testing.assert_allclose(right.solve(qp), expected, atol=1e-9, rtol=0)
    assert ActiveSet.none(n).solve(qp) is None  # leaves the box
    too_many = at_upper.copy()
    too_many[np.flatnonzero(free)[0]] = True  # a free joint held at its upper bound
    assert ActiveSet(too_many, at_lower).solve(qp) is None  # wrong multiplier
    too_few = at_upper.copy()
    too_few[np.flatnonzero(at_upper)[0]] = False  # a bound joint let free
    assert ActiveSet(too_few, at_lower).solve(qp) is None  # leaves its bound
    command = controller.step(state, reference, DT)  # after reset: the empty guess
    assert controller.diagnostics["solver"] == "osqp"
    np.testing.assert_allclose(command.qd, expected, atol=1e-6, rtol=0)
    # Allowed to change the set, the controller finds the solution from every wrong guess.
    for guess in (ActiveSet.none(n), ActiveSet(too_many, at_lower)):
        found = guess.search(qp, diff_ik_qp.ACTIVE_SET_CHANGES + 1)
        assert found is not None
        np.testing.assert_array_equal(found[0].upper, at_upper)
        np.testing.assert_array_equal(found[0].lower, at_lower)
        np.testing.assert_allclose(found[1], expected, atol=1e-9, rtol=0)
    searching = DiffIKQP(robot, ki=0.0, velocity_scale=scale)
    searching.reset(state)
    np.testing.assert_allclose(searching.step(state, reference, DT).qd, expected, atol=1e-9)
    assert searching.diagnostics["solver"] == "active set"


def test_commands_never_leave_the_limits_in_a_random_stress():
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(13)
    controller = DiffIKQP(robot, kp=500.0)
    q, reference = _random_case(robot, rng)
    controller.reset(State(0.0, q, np.zeros(robot.dof)))
    last = np.zeros(robot.dof)
    for k in range(300):
        # Jumpy references far away: every bound gets pushed.
        q_ref = np.clip(q + rng.normal(0.0, 0.3, robot.dof), limits.lower, limits.upper)
        qd_ref = rng.uniform(-1.5, 1.5, robot.dof) * limits.velocity
        reference = _reference(robot, q_ref, qd_ref)
        command = controller.step(State(k * DT, q, last), reference, DT)
        assert command.status == "ok", command.status
        assert np.all(np.abs(command.qd) <= limits.velocity * (1 + 1e-12))
        assert np.all(np.abs(command.qd - last) <= limits.acceleration * DT * (1 + 1e-9) + 1e-12)
        q = q + command.qd * DT
        assert np.all(q <= limits.upper + 1e-9) and np.all(q >= limits.lower - 1e-9)
        last = command.qd


def test_extra_constraint_rows_hold():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(14)
    q, reference = _random_case(robot, rng)
    J = robot.jacobian(q)
    cap = Constraint(J[:3][[0]], np.array([-0.003]), np.array([0.003]))  # tool x: 3 mm/s
    controller = DiffIKQP(robot, constraints=[cap], kp=200.0)
    state = State(0.0, q, np.zeros(robot.dof))
    controller.reset(state)
    free = DiffIKQP(robot, kp=200.0)
    free.reset(state)
    unconstrained = free.step(state, reference, DT).qd
    command = controller.step(state, reference, DT)
    assert command.status == "ok"
    assert abs(J[0] @ unconstrained) > 0.005  # the cap binds
    assert abs(J[0] @ command.qd) <= 0.003 + 1e-6


def test_failure_falls_back_to_braking_within_limits(monkeypatch):
    robot = get_robot("sawyer")
    limits = robot.limits
    q = robot.home
    last = 0.9 * limits.velocity
    controller = DiffIKQP(robot, active_set_changes=0)  # the step goes to OSQP
    state = State(0.0, q, last)
    controller.reset(state)

    def fail(self, qp):
        return False, "maximum iterations reached", 7, np.full(qp.c.size, np.nan), np.zeros(1)

    monkeypatch.setattr(OSQPWorkspace, "solve", fail)
    reference = _reference(robot, q, np.zeros(robot.dof))._replace(tau=np.ones(robot.dof))
    command = controller.step(state, reference, DT)
    assert command.fallback
    assert command.tau is None  # a safe fallback carries no feed-forward
    assert "maximum iterations reached" in command.status
    np.testing.assert_allclose(command.qd, last - limits.acceleration * DT)
    assert np.all(np.abs(command.qd) <= limits.velocity)


def test_posture_velocity_shifts_the_posture_term_by_the_planned_velocity():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(25)
    moving = DiffIKQP(robot, evaluation="pieces")
    resting = DiffIKQP(robot, evaluation="pieces", posture_velocity=False)
    for _ in range(10):
        q, reference = _random_case(robot, rng)
        state = State(0.0, q, np.zeros(robot.dof))
        for controller in (moving, resting):
            controller.reset(state)
        a, b = moving.build(state, reference, DT), resting.build(state, reference, DT)
        np.testing.assert_array_equal(a.H, b.H)
        np.testing.assert_allclose(
            a.c - b.c, -moving.posture_weight * reference.qd, rtol=0, atol=1e-15
        )
        assert np.abs(reference.qd).max() > 0.1  # the shift is not vacuous


@pytest.mark.parametrize("evaluation", ["fused", "pieces"])
def test_the_command_carries_the_plans_feed_forward_torque(evaluation):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(26)
    q, reference = _random_case(robot, rng)
    reference = reference._replace(tau=rng.normal(0.0, 5.0, robot.dof))
    state = State(0.0, q, np.zeros(robot.dof))
    commands = {}
    for feedforward in (True, False):
        controller = DiffIKQP(robot, evaluation=evaluation, feedforward=feedforward)
        controller.reset(state)
        commands[feedforward] = controller.step(state, reference, DT)
    np.testing.assert_array_equal(commands[True].tau, reference.tau)
    assert commands[False].tau is None
    # The feed-forward does not change the velocity command.
    np.testing.assert_array_equal(commands[True].qd, commands[False].qd)
    plain = DiffIKQP(robot, evaluation=evaluation)
    plain.reset(state)
    assert plain.step(state, reference._replace(tau=None), DT).tau is None


def test_pickled_controller_continues_with_the_same_commands():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(16)
    controller = DiffIKQP(robot)
    q, reference = _random_case(robot, rng)
    state = State(0.0, q, np.zeros(robot.dof))
    controller.reset(state)
    for _ in range(5):
        controller.step(state, reference, DT)
    clone = pickle.loads(pickle.dumps(controller))
    a = controller.step(state, reference, DT)
    b = clone.step(state, reference, DT)
    np.testing.assert_allclose(a.qd, b.qd, atol=1e-6)


def test_bad_settings_are_refused():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match="weights"):
        DiffIKQP(robot, weights=(-1.0, 1.0))
    with pytest.raises(InvalidInputError, match=r"velocity_scale must be in \[1e-06, 1\]"):
        DiffIKQP(robot, velocity_scale=1.5)
    with pytest.raises(InvalidInputError, match="posture_weight"):
        DiffIKQP(robot, posture_weight=-1.0)
    with pytest.raises(InvalidInputError, match="damping"):
        DiffIKQP(robot, damping=0.0)
    with pytest.raises(InvalidInputError, match="max_iterations"):
        DiffIKQP(robot, max_iterations=0)
    with pytest.raises(InvalidInputError, match="active_set_changes"):
        DiffIKQP(robot, active_set_changes=-1)
    with pytest.raises(InvalidInputError, match="limits cover 4 joints"):
        DiffIKQP(robot, limits=get_robot("paddle4").limits)
    with pytest.raises(InvalidInputError, match="Constraint rows"):
        DiffIKQP(robot, constraints=[(np.ones((1, 7)), 0.0, 1.0)])
    with pytest.raises(UnknownNameError, match="task"):
        DiffIKQP(robot, task="position")
    with pytest.raises(InvalidInputError, match="posture_velocity must be True or False"):
        DiffIKQP(robot, posture_velocity=1)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="feedforward must be True or False, got 'yes'"):
        DiffIKQP(robot, feedforward="yes")  # type: ignore[arg-type]


def test_a_step_cut_short_by_the_iteration_cap_is_still_used_when_it_checks_out():
    robot = get_robot("sawyer")
    for seed in (17, 18, 19):
        q, reference = _random_case(robot, np.random.default_rng(seed))
        exact = DiffIKQP(robot)
        capped = DiffIKQP(robot, max_iterations=6, active_set_changes=0)
        state = State(0.0, q, np.zeros(robot.dof))
        exact.reset(state)
        capped.reset(state)
        a = exact.step(state, reference, DT)
        b = capped.step(state, reference, DT)
        assert capped.diagnostics["status"] == "maximum iterations reached"
        assert b.status == "ok"
        np.testing.assert_allclose(b.qd, a.qd, atol=1e-6)  # the active set was right: exact


def test_bad_constraint_rows_are_refused():
    robot = get_robot("sawyer")
    G = np.ones((2, 7))
    with pytest.raises(InvalidInputError, match="constraint lower must be 2 numbers"):
        DiffIKQP(robot, constraints=[Constraint(G, np.zeros(3), np.ones(2))])
    with pytest.raises(InvalidInputError, match="not NaN"):
        DiffIKQP(robot, constraints=[Constraint(G, np.array([0.0, np.nan]), np.ones(2))])
    with pytest.raises(InvalidInputError, match=r"constraint row 1: lower 2 > upper 1"):
        DiffIKQP(robot, constraints=[Constraint(G, np.array([0.0, 2.0]), np.ones(2))])
    with pytest.raises(InvalidInputError, match="constraint G"):
        DiffIKQP(robot, constraints=[Constraint(np.ones((2, 6)), np.zeros(2), np.ones(2))])
    with pytest.raises(InvalidInputError, match=r"robots\.JointLimits"):
        DiffIKQP(robot, limits="fast")
    DiffIKQP(robot, max_iterations=np.int64(10))  # numpy integers are integers


def test_a_robot_that_is_not_a_robot_and_constraints_that_are_no_list_are_refused():
    with pytest.raises(InvalidInputError, match=r"robot must be a robots\.Robot"):
        DiffIKQP("sawyer")  # not an AttributeError
    with pytest.raises(InvalidInputError, match="constraints must be a list or tuple"):
        DiffIKQP(get_robot("paddle4"), constraints=5)  # not a TypeError
    with pytest.raises(InvalidInputError, match="posture_weight must be a numeric"):
        DiffIKQP(get_robot("paddle4"), posture_weight=True)
