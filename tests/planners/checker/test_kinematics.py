"""Tests of planners.checker.kinematics: batched tool poses and twists, against the robot."""

from __future__ import annotations

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, quintic

from optraj.planners.checker.kinematics import ToolKinematics
from optraj.planners.checker.polynomials import derivatives_of


def test_poses_and_twists_at_the_requested_instants_match_the_robot(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T)
    knots = np.asarray(trajectory.breakpoints)
    kinematics = ToolKinematics(paddle, derivatives_of(trajectory.coefficients, 1), knots)
    early, late = np.array([0.0, 0.3, 0.7]), np.array([1.1, 2.0])
    kinematics.need(early)
    kinematics.need(late, twist=True)
    kinematics.need(0.3)  # asked twice: computed once
    kinematics.compute()
    for times in (early, late, np.array([0.7, 0.0])):
        sample = trajectory.sample(times)
        np.testing.assert_allclose(
            kinematics.pose(times), paddle.tool_pose(sample.q), rtol=0, atol=1e-12
        )
    sample = trajectory.sample(late)
    twist = np.einsum("mij,mj->mi", paddle.jacobian(sample.q), sample.qd)
    np.testing.assert_allclose(kinematics.twist(late), twist, rtol=0, atol=1e-12)
    assert kinematics.pose(1.1).shape == (1, 4, 4)


def test_an_instant_that_was_not_requested_is_an_error(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T)
    knots = np.asarray(trajectory.breakpoints)
    kinematics = ToolKinematics(paddle, derivatives_of(trajectory.coefficients, 1), knots)
    kinematics.need([0.5])
    kinematics.compute()
    with pytest.raises(RuntimeError, match="not requested"):
        kinematics.pose([0.6])
    with pytest.raises(RuntimeError, match="not requested"):
        kinematics.pose([3.0])  # beyond every requested instant
    with pytest.raises(RuntimeError, match="not requested"):
        kinematics.twist([0.5])  # a pose, not a twist, was asked for
