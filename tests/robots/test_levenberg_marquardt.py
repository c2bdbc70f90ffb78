from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj.robots.levenberg_marquardt import (
    STALL_WINDOW,
    PoseError,
    levenberg_marquardt,
    levenberg_marquardt_batch,
)


def test_an_attempt_converges_within_the_limits_and_reports_its_errors():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(8)
    q_true = robot.random_configurations(1, rng)[0]
    T = robot.tool_pose(q_true)
    problem = PoseError(robot, robot.tool_frame_id, T[:3, 3], T[:3, :3].copy())
    start = robot.limits.clip(q_true + rng.uniform(-0.2, 0.2, robot.dof))
    attempt = levenberg_marquardt(problem, start, 1e-9, 500)
    assert attempt.worst_error <= 1e-9 and not attempt.stalled and attempt.iterations > 0
    assert np.all(attempt.q >= robot.limits.lower) and np.all(attempt.q <= robot.limits.upper)
    np.testing.assert_allclose(robot.tool_pose(attempt.q), T, atol=1e-8)


def test_a_stalling_attempt_is_given_up_only_when_asked():
    robot = get_robot("sawyer")
    far = np.array([5.0, 0.0, 0.5])  # out of reach: the error stops shrinking
    problem = PoseError(robot, robot.tool_frame_id, far)
    given_up = levenberg_marquardt(problem, robot.home, 1e-9, 500, stall=True)
    kept = levenberg_marquardt(problem, robot.home, 1e-9, 500)
    assert given_up.stalled and given_up.iterations >= STALL_WINDOW
    assert not kept.stalled and kept.iterations >= given_up.iterations
    assert given_up.position_error > 1.0


def test_batched_attempts_take_the_steps_each_takes_alone():
    # Random restarts run side by side; each must end where it ends run alone, here also
    # where the solution holds a joint on its lower limit (the held-joint steps).
    robot = get_robot("sawyer")
    rng = np.random.default_rng(5)
    q_true = robot.random_configurations(1, rng)[0]
    q_true[1] = robot.limits.lower[1]
    T = robot.tool_pose(q_true)
    problem = PoseError(robot, robot.tool_frame_id, T[:3, 3], None, T[:3, 2])
    starts = np.clip(
        q_true + rng.uniform(-0.3, 0.3, (16, robot.dof)), robot.limits.lower, robot.limits.upper
    )
    batch = levenberg_marquardt_batch(problem, starts, 1e-9, 500)
    on_limit = 0
    for start, together in zip(starts, batch, strict=True):
        alone = levenberg_marquardt(problem, start, 1e-9, 500)
        assert together.iterations == alone.iterations
        np.testing.assert_allclose(together.q, alone.q, rtol=0, atol=1e-12)
        assert together.worst_error <= 1e-9
        on_limit += bool(together.q[1] <= robot.limits.lower[1])
    assert on_limit >= 4  # the held-joint path was taken
