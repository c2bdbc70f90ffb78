"""Tests of planners.strike.pool_contact: the pool contact choice and contact_near.

References (tests/strike_support.py): the task rows rebuilt from the Jacobian, the LP optimum by
vertex enumeration, the window ratio and room-to-turn estimate from IK'd window ends; the pose
of each chosen configuration from forward kinematics.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from strike_support import by_vertices, pool_shots, reference_rows, turn_ratio, window_ratio

from optraj import problems
from optraj.errors import InvalidInputError, JointLimitError
from optraj.planners.strike.contact import ContactChoice, choose_contact, contact_choices
from optraj.planners.strike.pool_contact import contact_near
from optraj.planners.strike.twist_ratio import twist_ratio

#: Largest joint change [rad] expected between a branch's contact configurations for balls
#: 2 cm apart (contact_choices counts choices more than 0.1 rad apart as other branches).
_SPREAD_OF_A_BRANCH = 0.1


def test_pool_contact_leaves_the_cue_roll_joint_still():
    # Sawyer's last joint turns the cue about its own axis: no joint velocity needs it.
    for problem in pool_shots(3, speed=1.0):
        for choice in contact_choices(problem, 3):
            assert choice.qd[6] == 0.0
            assert choice.binding_joint != problem.robot.joint_names[6]


def test_pool_choice_is_on_the_line_and_beats_the_naive_branch():
    chosen_ratios, naive_ratios = [], []
    for problem in pool_shots(6, speed=1.0):
        robot, direction = problem.robot, np.asarray(problem.direction)
        vmax = problem.limits.velocity
        choice = choose_contact(problem)
        assert isinstance(choice, ContactChoice)
        for q, point in (
            (choice.q, problem.contact_point),
            (choice.q_entry, problem.entry_point),
            (choice.q_exit, problem.exit_point),
        ):
            pose = robot.tool_pose(q)
            np.testing.assert_allclose(pose[:3, 3], point, rtol=0, atol=1e-6)
            np.testing.assert_allclose(pose[:3, 2], direction, rtol=0, atol=1e-6)
            assert problem.limits.contains(q)
        # The contact joint velocity gives the strike twist (rows rebuilt here).
        rows, target = reference_rows(robot, choice.q, direction)
        np.testing.assert_allclose(rows @ choice.qd, target, rtol=0, atol=1e-9)
        contact_ratio = float(np.abs(choice.qd / vmax).max())
        np.testing.assert_allclose(contact_ratio, by_vertices(rows, target, vmax), rtol=1e-6)
        # The reported ratio is the window's largest, recomputed at the returned configurations.
        window = max(
            twist_ratio(robot, q, direction, 1.0)[0]
            for q in (choice.q, choice.q_entry, choice.q_exit)
        )
        np.testing.assert_allclose(choice.ratio, window, rtol=1e-9)
        assert choice.ratio >= contact_ratio - 1e-12
        np.testing.assert_allclose(choice.max_speed, 1.0 / choice.ratio, rtol=1e-12)
        assert choice.binding_joint in robot.joint_names
        assert choice.candidates >= 16
        naive = window_ratio(problem, problem.q_contact)
        if naive is not None:
            # The naive branch is a candidate; ranking may prefer room from the position
            # limits, at a cost of at most 2 % in ratio, or room to turn at them.
            cornered = turn_ratio(problem, problem.q_contact) > naive
            assert choice.ratio <= 1.02 * naive + 1e-12 or cornered
            chosen_ratios.append(choice.ratio)
            naive_ratios.append(naive)
    assert len(chosen_ratios) >= 4
    assert sum(r <= 1.0 for r in chosen_ratios) >= len(chosen_ratios) - 1
    # The search does materially better than the IK branch nearest the start.
    assert np.mean(chosen_ratios) <= 0.9 * np.mean(naive_ratios)


def test_self_motion_search_improves_a_single_start():
    # With one candidate (the IK branch nearest the start) only the pattern search along the
    # self-motion can lower the ratio. At a speed where that branch needs 95 % of a limit it
    # has no room to spare, so the choice is the smallest ratio found.
    improved, naive_ratios = [], []
    for shot in pool_shots(8, speed=0.5):
        unit = window_ratio(shot, shot.q_contact) / 0.5
        problem = dataclasses.replace(shot, speed=0.95 / unit)
        naive = window_ratio(problem, problem.q_contact)
        choice = choose_contact(problem, candidates=1)
        assert choice.candidates > 1
        np.testing.assert_allclose(
            choice.ratio,
            max(
                twist_ratio(problem.robot, q, problem.direction, problem.speed)[0]
                for q in (choice.q, choice.q_entry, choice.q_exit)
            ),
            rtol=1e-9,
        )
        cornered = turn_ratio(problem, problem.q_contact) > naive
        assert choice.ratio <= 1.02 * naive + 1e-12 or cornered
        improved.append(choice.ratio)
        naive_ratios.append(naive)
    assert np.mean(improved) <= 0.9 * np.mean(naive_ratios)


def test_with_room_to_spare_the_contact_nearest_the_start_is_chosen():
    # At 0.5 m/s the branch nearest the start usually has room; the choice may not be
    # farther from the start (joint travel time at the velocity limits) than that branch.
    checked = 0
    for problem in pool_shots(6, speed=0.5):
        if window_ratio(problem, problem.q_contact) > 0.9:
            continue
        choice = choose_contact(problem)
        assert choice.ratio <= 0.9
        vmax = problem.limits.velocity
        reach = np.max(np.abs(choice.q - problem.q_start) / vmax)
        naive_reach = np.max(np.abs(problem.q_contact - problem.q_start) / vmax)
        assert reach <= naive_reach + 1e-9
        checked += 1
    assert checked >= 3


def test_contact_near_follows_a_previous_branch_to_a_moved_ball():
    followed = 0
    for problem in pool_shots(6, speed=0.8):
        choice = choose_contact(problem)
        moved = dataclasses.replace(
            problem, ball=np.asarray(problem.ball) + np.array([0.0, 0.02, 0.0])
        )
        near = contact_near(moved, choice.q)
        if near is None:  # the branch lost its room: the caller searches instead
            continue
        followed += 1
        # On the moved line, with the ratio recomputed independently at its configurations.
        robot, direction = moved.robot, np.asarray(moved.direction)
        pose = robot.tool_pose(near.q)
        np.testing.assert_allclose(pose[:3, 3], moved.contact_point, rtol=0, atol=1e-6)
        np.testing.assert_allclose(pose[:3, 2], direction, rtol=0, atol=1e-6)
        ratio = max(
            twist_ratio(robot, q, direction, moved.speed)[0]
            for q in (near.q, near.q_entry, near.q_exit)
        )
        np.testing.assert_allclose(near.ratio, ratio, rtol=1e-9)
        assert near.ratio <= 0.9  # room to spare, or it would not be returned
        assert np.abs(near.q - choice.q).max() < _SPREAD_OF_A_BRANCH  # the same branch
    assert followed >= 4


def test_contact_near_declines_a_strike_without_room_and_bad_input():
    checked = 0
    for problem in pool_shots(4, speed=1.0):
        choice = choose_contact(problem)
        unit = choice.ratio / problem.speed
        slow = dataclasses.replace(problem, speed=0.5 / unit)
        kept = contact_near(slow, choice.q)
        if kept is None:  # a joint cornered at a limit: its room to turn decides
            continue
        checked += 1
        assert kept.ratio == pytest.approx(0.5, rel=1e-6)  # the same configuration
        fast = dataclasses.replace(problem, speed=0.95 / unit)
        assert contact_near(fast, choice.q) is None  # 95 % of a limit: no room to spare
        assert contact_near(slow, choice.q, margin=0.5) is None  # 50 % > 0.9 x (1 - 0.5)
    assert checked >= 2
    with pytest.raises(InvalidInputError, match="margin"):
        contact_near(problem, choice.q, margin=1.0)
    with pytest.raises(InvalidInputError, match="q must have shape"):
        contact_near(problem, choice.q[:3])
    with pytest.raises(InvalidInputError, match="PoolStrike"):
        contact_near(problems.ece486_paddle_strike(), choice.q)
    beyond = choice.q.copy()
    beyond[1] = problem.limits.upper[1] + 0.5
    with pytest.raises(JointLimitError, match="contact_near q: joint 'right_j1'") as info:
        contact_near(problem, beyond)
    assert info.value.joint == "right_j1"
