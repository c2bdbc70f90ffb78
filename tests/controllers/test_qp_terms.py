from __future__ import annotations

import numpy as np
import pytest

from optraj.controllers.qp_terms import (
    Bounds,
    Constraint,
    Objective,
    acceleration_bounds,
    combine,
    damping_objective,
    position_bounds,
    posture_objective,
    task_objective,
    task_weights,
    velocity_bounds,
)
from optraj.errors import InvalidInputError


def _value(objective: Objective, x: np.ndarray) -> float:
    return 0.5 * x @ objective.H @ x + objective.c @ x


def test_task_objective_is_the_weighted_squared_error_up_to_a_constant():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(6, 7))
    v = rng.normal(size=6)
    W = task_weights(2.0, 0.5)
    objective = task_objective(J, v, W)
    constant = 0.5 * v @ W @ v
    for _ in range(5):
        x = rng.normal(size=7)
        r = J @ x - v
        np.testing.assert_allclose(_value(objective, x) + constant, 0.5 * r @ W @ r, rtol=1e-12)


def test_task_objective_with_diagonal_weights_equals_the_full_matrix():
    rng = np.random.default_rng(4)
    J = rng.normal(size=(6, 7))
    v = rng.normal(size=6)
    W = task_weights(2.0, 0.5)
    full, diagonal = task_objective(J, v, W), task_objective(J, v, np.diag(W))
    np.testing.assert_allclose(diagonal.H, full.H, rtol=1e-14)
    np.testing.assert_allclose(diagonal.c, full.c, rtol=1e-14)


def test_axis_weights_ignore_rotation_about_the_axis():
    axis = np.array([0.0, 0.6, 0.8])
    W = task_weights(1.0, 3.0, axis=axis)
    np.testing.assert_allclose(W[3:, 3:] @ axis, 0.0, atol=1e-15)
    other = np.cross(axis, [1.0, 0.0, 0.0])
    np.testing.assert_allclose(W[3:, 3:] @ other, 3.0 * other, rtol=1e-12)
    np.testing.assert_allclose(W[:3, :3], np.eye(3))


def test_damping_and_posture_objectives():
    rng = np.random.default_rng(2)
    x = rng.normal(size=4)
    np.testing.assert_allclose(_value(damping_objective(4, 0.3), x), 0.15 * x @ x)
    q, q_posture = rng.normal(size=4), rng.normal(size=4)
    posture = posture_objective(q, q_posture, weight=0.2, gain=5.0)
    target = 5.0 * (q_posture - q)
    expected = 0.1 * np.sum((x - target) ** 2) - 0.1 * target @ target
    np.testing.assert_allclose(_value(posture, x), expected, rtol=1e-12)


def test_posture_objective_with_a_posture_velocity_is_the_formula():
    rng = np.random.default_rng(5)
    for n in (4, 7):
        q, q_posture, qd_posture = rng.normal(size=(3, n))
        weight, gain = rng.uniform(1e-3, 1.0), rng.uniform(0.5, 20.0)
        posture = posture_objective(q, q_posture, weight, gain, qd_posture)
        # w/2 ||x - (qd_p + k (q_p - q))||^2, up to the constant w/2 ||target||^2.
        target = qd_posture + gain * (q_posture - q)
        for _ in range(5):
            x = rng.normal(size=n)
            expected = 0.5 * weight * np.sum((x - target) ** 2) - 0.5 * weight * target @ target
            np.testing.assert_allclose(_value(posture, x), expected, rtol=1e-12, atol=1e-14)
        # Its minimiser is the target velocity.
        np.testing.assert_allclose(
            np.linalg.solve(posture.H, -posture.c), target, rtol=1e-12, atol=1e-14
        )
        # None is a posture at rest, the same as a zero velocity.
        at_rest = posture_objective(q, q_posture, weight, gain)
        zero = posture_objective(q, q_posture, weight, gain, np.zeros(n))
        np.testing.assert_array_equal(at_rest.c, zero.c)
        np.testing.assert_array_equal(at_rest.H, posture.H)
        np.testing.assert_allclose(
            at_rest.c - posture.c, weight * qd_posture, rtol=1e-12, atol=1e-13
        )


def test_velocity_and_acceleration_bounds():
    box = velocity_bounds(np.array([1.0, 2.0]), scale=0.5)
    np.testing.assert_allclose(box.lower, [-0.5, -1.0])
    np.testing.assert_allclose(box.upper, [0.5, 1.0])
    box = acceleration_bounds(np.array([0.2, -0.1]), np.array([10.0, 5.0]), dt=0.01)
    np.testing.assert_allclose(box.lower, [0.1, -0.15])
    np.testing.assert_allclose(box.upper, [0.3, -0.05])


def test_position_bounds_leave_room_to_brake_and_push_back_from_beyond():
    lower, upper = np.array([-1.0, -1.0, -1.0]), np.array([1.0, 1.0, 1.0])
    acceleration = np.full(3, 2.0)
    dt = 0.001
    q = np.array([0.0, 0.99, 1.01])  # far, close to, beyond the upper limit
    box = position_bounds(q, lower, upper, acceleration, dt=dt, gain=0.95)
    assert box.upper[0] < np.sqrt(2 * 2.0 * 1.0)  # below the continuous-time braking speed
    assert box.upper[1] < 0.95 * 0.01 / dt
    assert box.upper[2] < 0.0  # beyond: must move back
    np.testing.assert_allclose(box.upper[2], 0.95 * -0.01 / dt)
    mirrored = position_bounds(-q, lower, upper, acceleration, dt=dt, gain=0.95)
    np.testing.assert_allclose(mirrored.lower, -box.upper)  # symmetric below


@pytest.mark.parametrize("dt", [1e-3, 4e-3, 2e-2])
def test_braking_from_the_position_bound_stops_at_the_limit(dt):
    # A joint commanded step by step: as fast as the bounds allow towards the upper limit,
    # never changing speed by more than a dt per step. It must stop without crossing it.
    rng = np.random.default_rng(int(dt * 1e4))
    for _ in range(20):
        a = rng.uniform(0.5, 10.0)
        q, v = -rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)
        lower, upper = np.array([-10.0]), np.array([0.0])
        reached = q
        for _ in range(100_000):
            box = position_bounds(np.array([q]), lower, upper, np.array([a]), dt=dt, gain=1.0)
            # As fast as allowed; the acceleration limit comes first, as in combine().
            v = max(min(v + a * dt, float(box.upper[0])), v - a * dt, 0.0)
            q += v * dt
            reached = max(reached, q)
            if v == 0.0 and box.upper[0] <= a * dt * 1e-9:
                break
        assert reached <= 1e-12, (a, dt, reached)


def test_braking_bound_never_asks_more_deceleration_than_allowed():
    dt, a = 1e-3, 3.0
    lower, upper = np.array([-1.0]), np.array([1.0])
    q, v = 0.0, 0.0
    for _ in range(5000):
        box = position_bounds(np.array([q]), lower, upper, np.array([a]), dt=dt, gain=1.0)
        wanted = min(float(box.upper[0]), v + a * dt)
        assert wanted >= v - a * dt - 1e-12  # the bound never drops faster than a dt per step
        v = wanted
        q += v * dt
    assert q <= upper[0]


def test_combine_adds_objectives_and_stacks_constraint_rows():
    rng = np.random.default_rng(3)
    a = Objective(np.eye(3), rng.normal(size=3))
    b = Objective(2 * np.eye(3), rng.normal(size=3))
    G = rng.normal(size=(2, 3))
    qp = combine([a, b], [velocity_bounds(np.ones(3))], [Constraint(G, -np.ones(2), np.ones(2))])
    np.testing.assert_allclose(qp.H, 3 * np.eye(3))
    np.testing.assert_allclose(qp.c, a.c + b.c)
    np.testing.assert_allclose(qp.A, np.vstack([np.eye(3), G]))
    np.testing.assert_allclose(qp.lower, [-1, -1, -1, -1, -1])
    assert qp.relaxed == ()


def test_combine_intersects_bounds():
    objective = damping_objective(2, 1.0)
    first = Bounds(np.array([-1.0, -1.0]), np.array([1.0, 1.0]), "velocity")
    second = Bounds(np.array([-0.5, 0.2]), np.array([2.0, 0.4]), "acceleration")
    qp = combine([objective], [first, second])
    np.testing.assert_allclose(qp.lower, [-0.5, 0.2])
    np.testing.assert_allclose(qp.upper, [1.0, 0.4])


def test_combine_relaxes_a_conflicting_lower_priority_bound_to_the_nearest_value():
    objective = damping_objective(2, 1.0)
    first = Bounds(np.array([0.5, -1.0]), np.array([0.8, -0.6]), "acceleration")
    # Joint 0 wants to go below 0.2, joint 1 above -0.3: both out of the first interval.
    second = Bounds(np.array([-1.0, -0.3]), np.array([0.2, 1.0]), "position")
    qp = combine([objective], [first, second])
    np.testing.assert_allclose(qp.lower, [0.5, -0.6])
    np.testing.assert_allclose(qp.upper, [0.5, -0.6])
    assert qp.relaxed == ("position",)


def test_combine_rejects_bad_pieces():
    with pytest.raises(InvalidInputError, match="at least one objective"):
        combine([])
    with pytest.raises(InvalidInputError, match="objective shapes"):
        combine([damping_objective(2, 1.0), damping_objective(3, 1.0)])
    bad = Bounds(np.array([1.0, 0.0]), np.array([0.0, 1.0]), "velocity")
    with pytest.raises(InvalidInputError, match="velocity bounds of joint 0"):
        combine([damping_objective(2, 1.0)], [bad])
    with pytest.raises(InvalidInputError, match=r"shape \(m, 2\)"):
        combine([damping_objective(2, 1.0)], [], [Constraint(np.ones((1, 3)), [0.0], [1.0])])


@pytest.mark.parametrize(
    ("arguments", "match"),
    [
        (([5],), "objectives must be a list or tuple of controllers.Objective"),
        (([Objective(np.eye(2), np.zeros(2))], [(0.0, 1.0)]), "bounds must be a list or tuple"),
        (([Objective(np.eye(2), np.zeros(2))], [], 5), "constraints must be a list or tuple"),
    ],
)
def test_combine_refuses_pieces_of_the_wrong_kind(arguments, match):
    # A typed error, not an AttributeError (.c, .lower) or a TypeError (iterating 5).
    with pytest.raises(InvalidInputError, match=match):
        combine(*arguments)
