"""Tests of planners.strike.contact: the strike LP against independent references, the choice.

References: the LP optimum by enumerating every vertex of the LP (numpy) and by scipy's
linprog on the full formulation (joint velocities as variables, task rows as equalities); the
task rows rebuilt here from the Jacobian (and, for the paddle's ball point, by finite
differences of its position); the pose of each chosen configuration from forward kinematics.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import time

import numpy as np
import pytest
from conftest import get_robot, race
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import null_space
from scipy.optimize import linprog

from optraj import problems
from optraj.errors import (
    CONTACT_CHOICE,
    InfeasibleError,
    InvalidInputError,
    JointLimitError,
    UnreachableError,
)
from optraj.planners.profiles.cartesian import paddle_contact_velocity
from optraj.planners.strike.contact import (
    ContactChoice,
    _MinMaxRatio,
    choose_contact,
    contact_choices,
    contact_near,
    stopping_speeds,
    twist_ratio,
)
from optraj.robots import solve_ik
from optraj.robots.paddle_ik import BALL_OFFSET

#: Largest joint change [rad] expected between a branch's contact configurations for balls
#: 2 cm apart (contact_choices counts choices more than 0.1 rad apart as other branches).
_SPREAD_OF_A_BRANCH = 0.1

# ------------------------------------------------------------------------ references


def _rows(robot, q, direction, align_axis=True):
    """Task rows rebuilt from the Jacobian: tool-origin velocity; angular velocity across d."""
    jac = robot.jacobian(q)
    across = null_space(direction[None, :]).T  # (2, 3), orthonormal, perpendicular to d
    rows = [jac[:3]] + ([across @ jac[3:]] if align_axis else [])
    target = np.concatenate([direction] + ([np.zeros(2)] if align_axis else []))
    return np.vstack(rows), target


def _by_vertices(rows, target, vmax):
    """min over rows @ qd = target of max |qd_i| / vmax_i, by enumerating the LP's vertices.

    In y = qd / vmax = y0 + N z the feasible set {(z, s): |y0 + N z| <= s} has no lines
    (N has full column rank), so the optimum is at a vertex: k + 1 active constraints.
    """
    scaled = rows * vmax
    y0 = np.linalg.lstsq(scaled, target, rcond=None)[0]
    null = null_space(scaled)
    k = null.shape[1]
    if k == 0:
        return float(np.abs(y0).max())
    sides = [(i, sign) for i in range(vmax.size) for sign in (1.0, -1.0)]
    best = math.inf
    for combo in itertools.combinations(sides, k + 1):
        lhs = np.array([[*(sign * null[i]), -1.0] for i, sign in combo])
        if abs(np.linalg.det(lhs)) < 1e-12:
            continue
        x = np.linalg.solve(lhs, [-sign * y0[i] for i, sign in combo])
        if np.abs(y0 + null @ x[:k]).max() <= x[k] + 1e-9:
            best = min(best, float(x[k]))
    return best


def _by_linprog(rows, target, vmax):
    """The same LP with the joint velocities as variables, solved by scipy."""
    n = vmax.size
    bound = np.block([[np.eye(n), -vmax[:, None]], [-np.eye(n), -vmax[:, None]]])
    result = linprog(
        np.r_[np.zeros(n), 1.0],
        A_ub=bound,
        b_ub=np.zeros(2 * n),
        A_eq=np.c_[rows, np.zeros(rows.shape[0])],
        b_eq=target,
        bounds=[(None, None)] * n + [(0.0, None)],
    )
    assert result.status == 0, result.message
    return float(result.fun)


def _ball_point_jacobian(robot, q, step=1e-6):
    """d(ball point)/dq by central differences of the ball point's position."""

    def point(config):
        pose = robot.tool_pose(config)
        return pose[:3, 3] + BALL_OFFSET * pose[:3, 2]

    columns = []
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = step
        columns.append((point(q + dq) - point(q - dq)) / (2 * step))
    return np.array(columns).T


def _unit(rng):
    vector = rng.normal(size=3)
    return vector / np.linalg.norm(vector)


def _shots(count, speed, seed=7):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        ball = (rng.uniform(0.65, 0.85), rng.uniform(-0.05, 0.3), rng.uniform(-0.1, 0.0))
        yield problems.sawyer_pool_shot(speed, ball, heading_deg=rng.uniform(-20.0, 20.0))


def _window_ratio(problem, q):
    """Largest ratio over contact, entry and exit, the ends solved by IK from q (None if not)."""
    robot, direction = problem.robot, problem.direction
    ratios = [twist_ratio(robot, q, direction, problem.speed)[0]]
    for point in (problem.entry_point, problem.exit_point):
        try:
            end = solve_ik(robot, point, axis=direction, q_near=q, restarts=0).q
        except UnreachableError:
            return None
        ratios.append(twist_ratio(robot, end, direction, problem.speed)[0])
    return max(ratios)


def _turn_ratio(problem, q):
    """The documented room-to-turn estimate at the strike's speed, from IK'd window ends."""
    robot, direction, limits = problem.robot, problem.direction, problem.limits
    entry, leave = (
        solve_ik(robot, point, axis=direction, q_near=q, restarts=0).q
        for point in (problem.entry_point, problem.exit_point)
    )
    worst = 0.0
    for end, rate in (
        (entry, (q - entry) / problem.run_up),  # must have turned before: room behind
        (leave, (leave - q) / problem.follow_through),  # must stop after: room ahead
    ):
        behind = end is entry
        for j in np.flatnonzero(rate):
            up = (rate[j] > 0) != behind
            room = limits.upper[j] - end[j] if up else end[j] - limits.lower[j]
            need = problem.speed * abs(rate[j]) / np.sqrt(2 * limits.acceleration[j] * max(room, 0))
            worst = max(worst, need)
    return worst


# ---------------------------------------------------------------------------- twist_ratio


def test_twist_ratio_meets_the_rows_and_equals_two_independent_optima():
    robot = get_robot("sawyer")
    vmax = robot.limits.velocity
    rng = np.random.default_rng(3)
    for q in robot.random_configurations(8, rng):
        direction = _unit(rng)
        speed = rng.uniform(0.2, 2.0)
        ratio, qd, joint = twist_ratio(robot, q, direction, speed)
        rows, target = _rows(robot, q, direction)
        np.testing.assert_allclose(rows @ qd, speed * target, rtol=0, atol=1e-9)
        np.testing.assert_allclose(np.abs(qd / vmax).max(), ratio, rtol=1e-12)
        assert abs(qd[joint]) / vmax[joint] == pytest.approx(ratio, rel=1e-9)
        np.testing.assert_allclose(ratio, speed * _by_vertices(rows, target, vmax), rtol=1e-6)
        np.testing.assert_allclose(ratio, speed * _by_linprog(rows, target, vmax), rtol=1e-6)
        # The LP beats the least-squares joint velocity (minimum norm, not minimum ratio).
        least_squares = np.linalg.lstsq(rows, speed * target, rcond=None)[0]
        assert ratio <= np.abs(least_squares / vmax).max() + 1e-12


@settings(max_examples=40, derandomize=True, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), align_axis=st.booleans())
def test_twist_ratio_stress_against_vertex_enumeration(seed, align_axis):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(seed)
    q = robot.random_configurations(1, rng)[0]
    direction = _unit(rng)
    ratio, qd, _ = twist_ratio(robot, q, direction, 1.0, align_axis=align_axis)
    rows, target = _rows(robot, q, direction, align_axis)
    np.testing.assert_allclose(rows @ qd, target, rtol=0, atol=1e-9)
    reference = _by_vertices(rows, target, robot.limits.velocity)
    np.testing.assert_allclose(ratio, reference, rtol=1e-6)


def test_twist_ratio_is_linear_in_speed_and_zero_at_rest():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(5)
    q = robot.random_configurations(1, rng)[0]
    direction = _unit(rng)
    unit_ratio, _, unit_joint = twist_ratio(robot, q, direction, 1.0)
    for speed in (0.3, 2.7):
        ratio, qd, joint = twist_ratio(robot, q, direction, speed)
        np.testing.assert_allclose(ratio, speed * unit_ratio, rtol=1e-9)
        assert joint == unit_joint
        np.testing.assert_allclose(np.abs(qd / robot.limits.velocity).max(), ratio, rtol=1e-12)
    ratio, qd, joint = twist_ratio(robot, q, direction, 0.0)
    assert (ratio, joint) == (0.0, 0)
    np.testing.assert_array_equal(qd, np.zeros(robot.dof))


def test_twist_ratio_uses_the_given_velocity_limits():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(6)
    q = robot.random_configurations(1, rng)[0]
    direction = _unit(rng)
    halved = robot.limits.velocity / 2.0
    slow = dataclasses.replace(robot.limits, velocity=halved)
    ratio, _, _ = twist_ratio(robot, q, direction, 1.0, limits=slow)
    rows, target = _rows(robot, q, direction)
    np.testing.assert_allclose(ratio, _by_vertices(rows, target, halved), rtol=1e-6)
    np.testing.assert_allclose(ratio, 2.0 * twist_ratio(robot, q, direction, 1.0)[0], rtol=1e-6)


def test_ball_point_rows_match_finite_differences():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(8)
    for q in robot.random_configurations(5, rng):
        direction = _unit(rng)
        ratio, qd, _ = twist_ratio(robot, q, direction, 0.8, offset=BALL_OFFSET, align_axis=False)
        jac = _ball_point_jacobian(robot, q)
        np.testing.assert_allclose(jac @ qd, 0.8 * direction, rtol=0, atol=1e-6)
        reference = _by_vertices(jac, direction, robot.limits.velocity)
        np.testing.assert_allclose(ratio, 0.8 * reference, rtol=1e-5)


def test_rank_deficient_rows_with_a_solution_give_the_analytic_optimum():
    # paddle4 turns about z only: the two angular rows across z vanish (rank 3 of 5), and only
    # the vertical prismatic J1 moves the paddle up, so qd = (v, 0, 0, 0) exactly.
    robot = get_robot("paddle4")
    q = robot.random_configurations(1, np.random.default_rng(9))[0]
    ratio, qd, joint = twist_ratio(robot, q, [0.0, 0.0, 1.0], 0.4)
    np.testing.assert_allclose(qd, [0.4, 0.0, 0.0, 0.0], rtol=0, atol=1e-12)
    assert ratio == pytest.approx(0.4 / robot.limits.velocity[0], rel=1e-12)
    assert joint == 0


def test_a_motion_the_arm_cannot_make_has_an_infinite_ratio():
    # youBot moves its tool sideways (along its pitch axes) only by yawing the base, which
    # turns the tool across that direction: with the axis held, no joint velocity does it.
    robot = get_robot("youbot")
    for q in robot.random_configurations(3, np.random.default_rng(10)):
        sideways = robot.jacobian(q)[3:, 1]
        rows, target = _rows(robot, q, sideways)
        residual = rows @ np.linalg.lstsq(rows, target, rcond=None)[0] - target
        assert np.linalg.norm(residual) > 1e-3  # independent: no exact solution
        ratio, qd, joint = twist_ratio(robot, q, sideways, 1.0)
        assert ratio == math.inf and joint == -1 and np.all(np.isnan(qd))
        assert math.isfinite(twist_ratio(robot, q, sideways, 1.0, align_axis=False)[0])


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"q": np.zeros(3)}, "q"),
        ({"direction": [0.0, 0.0, 0.0]}, "direction"),
        ({"direction": [np.nan, 0.0, 1.0]}, "direction"),
        ({"speed": -1.0}, "speed"),
        ({"offset": np.inf}, "offset"),
        ({"offset": 1e300}, "offset"),
        ({"limits": "sawyer"}, "limits"),
    ],
)
def test_twist_ratio_rejects_bad_input(kwargs, name):
    robot = get_robot("sawyer")
    arguments = {"q": robot.home, "direction": [1.0, 0.0, 0.0], "speed": 1.0, **kwargs}
    extra = {key: arguments.pop(key) for key in ("offset", "limits") if key in arguments}
    with pytest.raises(InvalidInputError) as info:
        twist_ratio(robot, arguments["q"], arguments["direction"], arguments["speed"], **extra)
    assert info.value.name == name
    with pytest.raises(InvalidInputError, match=r"robots\.Robot"):
        twist_ratio("sawyer", robot.home, [1.0, 0.0, 0.0], 1.0)


# ------------------------------------------------------------- the LP's NumPy path


def _random_lp(rng, kind):
    """A consistent system M y = b with a null space of dimension 1 or 2, of one of 6 kinds.

    0 generic; 1 a repeated row (rank below the row count); 2 a zero column (a joint that moves
    nothing); 3 entries in {-1, 0, 1} (ties between rows); 4 b = 0; 5 a column scaled by 1e-12.
    """
    n = int(rng.integers(3, 9))
    k = int(rng.integers(1, 3))
    M = rng.normal(size=(n - k, n))
    if kind == 1 and M.shape[0] >= 2:
        M = np.vstack([M, M[0] * rng.normal()])
    elif kind == 2:
        M[:, rng.integers(n)] = 0.0
    elif kind == 3:
        M = rng.integers(-1, 2, size=(n - k, n)).astype(float)
    elif kind == 5:
        M[:, rng.integers(n)] *= 1e-12
    b = np.zeros(M.shape[0]) if kind == 4 else M @ rng.normal(size=n)
    return M, b


def _null_space_problem(M, b):
    """y0 and N as _MinMaxRatio builds them (independently: lstsq and scipy's null_space)."""
    null = null_space(M, rcond=1e-10)
    y0 = np.linalg.lstsq(M, b, rcond=1e-10)[0]
    return y0 - null @ (null.T @ y0), null


@pytest.mark.parametrize("seed", range(6))
def test_numpy_lp_agrees_with_highs_on_random_and_degenerate_problems(seed):
    rng = np.random.default_rng(100 + seed)
    lp = _MinMaxRatio()
    checked = 0
    for trial in range(150):
        kind = trial % 6
        M, b = _random_lp(rng, kind)
        y = lp(M, b)
        assert y is not None
        scale = 1.0 + float(np.abs(b).max())
        np.testing.assert_allclose(M @ y, b, rtol=0, atol=1e-9 * scale)
        y0, null = _null_space_problem(M, b)
        if not np.any(np.abs(y0) > 1e-14) or null.shape[1] == 0:
            np.testing.assert_allclose(y, 0.0, atol=1e-12)  # b = 0: standing still is optimal
            continue
        ratio = float(np.abs(y).max())
        highs = float(np.abs(lp.highs(y0, null)).max())
        reference = _by_vertices(M, b, np.ones(M.shape[1]))
        assert ratio == pytest.approx(highs, rel=1e-9)
        assert ratio == pytest.approx(reference, rel=1e-9)
        checked += 1
    assert checked >= 100


def test_numpy_lp_returns_the_least_norm_minimiser_and_leaves_idle_joints_still():
    lp = _MinMaxRatio()
    # Only the first joint moves the row: the others are free up to its ratio (a square of
    # minimisers for k = 2, an interval for k = 1); the least-norm one keeps them still.
    for M in (np.array([[2.0, 0.0, 0.0]]), np.array([[2.0, 0.0], [0.0, 0.0]])):
        y = lp(M, np.r_[1.0, np.zeros(M.shape[0] - 1)])
        np.testing.assert_allclose(y, np.r_[0.5, np.zeros(M.shape[1] - 1)], rtol=0, atol=1e-15)
    # The ratio is set by joints 0 and 1 together (y0 + y1 = 1): 0.5 each, and joint 2, free up
    # to 0.5, stays still although every y2 in [-0.5, 0.5] is optimal.
    y = lp(np.array([[1.0, 1.0, 0.0]]), np.array([1.0]))
    np.testing.assert_allclose(y, [0.5, 0.5, 0.0], rtol=0, atol=1e-15)
    # A column far shorter than the others (a joint that moves nothing) stays exactly still.
    rng = np.random.default_rng(7)
    M = rng.normal(size=(5, 7))
    M[:, 6] = 1e-11 * rng.normal(size=5)
    b = M @ rng.normal(size=7)
    y = lp(M, b)
    assert y[6] == 0.0
    np.testing.assert_allclose(M @ y, b, rtol=0, atol=1e-9)
    reduced = lp(M[:, :6], b)
    np.testing.assert_array_equal(y[:6], reduced)


def test_numpy_lp_reports_a_motion_the_rows_cannot_give():
    lp = _MinMaxRatio()
    assert lp(np.array([[1.0, 0.0], [1.0, 0.0]]), np.array([1.0, 2.0])) is None
    assert lp(np.zeros((2, 3)), np.array([1.0, 0.0])) is None
    np.testing.assert_array_equal(lp(np.zeros((2, 3)), np.zeros(2)), np.zeros(3))


def test_pool_contact_leaves_the_cue_roll_joint_still():
    # Sawyer's last joint turns the cue about its own axis: no joint velocity needs it.
    for problem in _shots(3, speed=1.0):
        for choice in contact_choices(problem, 3):
            assert choice.qd[6] == 0.0
            assert choice.binding_joint != problem.robot.joint_names[6]


# ------------------------------------------------------------------- choose_contact: pool


def test_pool_choice_is_on_the_line_and_beats_the_naive_branch():
    chosen_ratios, naive_ratios = [], []
    for problem in _shots(6, speed=1.0):
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
        rows, target = _rows(robot, choice.q, direction)
        np.testing.assert_allclose(rows @ choice.qd, target, rtol=0, atol=1e-9)
        contact_ratio = float(np.abs(choice.qd / vmax).max())
        np.testing.assert_allclose(contact_ratio, _by_vertices(rows, target, vmax), rtol=1e-6)
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
        naive = _window_ratio(problem, problem.q_contact)
        if naive is not None:
            # The naive branch is a candidate; ranking may prefer room from the position
            # limits, at a cost of at most 2 % in ratio, or room to turn at them.
            cornered = _turn_ratio(problem, problem.q_contact) > naive
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
    for shot in _shots(8, speed=0.5):
        unit = _window_ratio(shot, shot.q_contact) / 0.5
        problem = dataclasses.replace(shot, speed=0.95 / unit)
        naive = _window_ratio(problem, problem.q_contact)
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
        cornered = _turn_ratio(problem, problem.q_contact) > naive
        assert choice.ratio <= 1.02 * naive + 1e-12 or cornered
        improved.append(choice.ratio)
        naive_ratios.append(naive)
    assert np.mean(improved) <= 0.9 * np.mean(naive_ratios)


def test_with_room_to_spare_the_contact_nearest_the_start_is_chosen():
    # At 0.5 m/s the branch nearest the start usually has room; the choice may not be
    # farther from the start (joint travel time at the velocity limits) than that branch.
    checked = 0
    for problem in _shots(6, speed=0.5):
        if _window_ratio(problem, problem.q_contact) > 0.9:
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
    for problem in _shots(6, speed=0.8):
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
    for problem in _shots(4, speed=1.0):
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
        contact_near(problems.seed_paddle_strike(), choice.q)
    beyond = choice.q.copy()
    beyond[1] = problem.limits.upper[1] + 0.5
    with pytest.raises(JointLimitError, match="contact_near q: joint 'right_j1'") as info:
        contact_near(problem, beyond)
    assert info.value.joint == "right_j1"


def test_pool_choice_is_reproducible_for_a_seed():
    problem = next(_shots(1, speed=1.0, seed=21))
    first, second = choose_contact(problem, seed=4), choose_contact(problem, seed=4)
    np.testing.assert_array_equal(first.q, second.q)
    np.testing.assert_array_equal(first.qd, second.qd)
    assert (first.ratio, first.binding_joint, first.candidates) == (
        second.ratio,
        second.binding_joint,
        second.candidates,
    )


def test_pool_choice_is_the_same_from_concurrent_threads():
    problem = next(_shots(1, speed=1.0, seed=21))
    expected = choose_contact(problem, candidates=4)
    results: dict[int, ContactChoice] = {}

    def worker(k):
        results[k] = choose_contact(problem, candidates=4)

    assert race(worker, 3) == []
    for choice in results.values():
        np.testing.assert_array_equal(choice.q, expected.q)
        np.testing.assert_array_equal(choice.qd, expected.qd)


def test_too_fast_pool_strike_is_rejected_within_a_second_and_the_bound_is_exact():
    problem = next(_shots(1, speed=2.5, seed=11))
    robot = problem.robot
    elapsed, errors = [], []
    for _ in range(2):  # the first call may load HiGHS; the second is the steady state
        started = time.perf_counter()
        with pytest.raises(InfeasibleError) as info:
            choose_contact(problem)
        elapsed.append(time.perf_counter() - started)
        errors.append(info.value)
    assert elapsed[1] < 1.0, f"rejection took {elapsed} s"
    error = errors[1]
    assert error.limit == "velocity"
    assert error.joint in robot.joint_names
    j = robot.joint_names.index(error.joint)
    assert error.allowed == pytest.approx(problem.limits.velocity[j])
    assert error.required > error.allowed
    assert error.joint in str(error) and "2.5 m/s" in str(error)
    assert 0.0 < error.max_speed < 2.5
    assert error.found_by == CONTACT_CHOICE
    # Same geometry at other speeds: the ratios scale, so the reported speed is the boundary.
    choice = choose_contact(dataclasses.replace(problem, speed=0.99 * error.max_speed))
    assert 0.98 <= choice.ratio <= 1.0
    with pytest.raises(InfeasibleError):
        choose_contact(dataclasses.replace(problem, speed=1.01 * error.max_speed))


def test_margin_keeps_part_of_the_velocity_limits_in_reserve():
    problem = next(_shots(1, speed=1.0, seed=11))
    with pytest.raises(InfeasibleError) as too_fast:
        choose_contact(dataclasses.replace(problem, speed=10.0))
    ratio = 1.0 / too_fast.value.max_speed  # the smallest ratio found at 1 m/s
    margin = 1.0 - 0.9 * ratio  # asks for ratio <= 0.9 * the best one found
    with pytest.raises(InfeasibleError, match="margin") as info:
        choose_contact(problem, margin=margin)
    error = info.value
    j = problem.robot.joint_names.index(error.joint)
    assert error.allowed == pytest.approx((1.0 - margin) * problem.limits.velocity[j])
    assert error.required > error.allowed
    assert 0.9 - 1e-9 <= error.max_speed <= 0.9 * 1.02
    assert choose_contact(problem, margin=1.0 - 1.01 * ratio).ratio <= 1.01 * ratio


# ----------------------------------------------------------------- choose_contact: paddle


def test_paddle_at_rest_needs_no_joint_velocity():
    problem = problems.PaddleStrike(get_robot("paddle4"), ball=(1.0, 0.3, 0.4), contact_angle=0.3)
    choice = choose_contact(problem)
    np.testing.assert_array_equal(choice.q, problem.q_contact)
    np.testing.assert_array_equal(choice.qd, np.zeros(4))
    assert choice.ratio == 0.0 and choice.q_entry is None and choice.q_exit is None
    assert math.isfinite(choice.max_speed) and choice.binding_joint in problem.robot.joint_names


@pytest.mark.parametrize(
    ("ball", "angle"), [((1.0, 0.3, 0.4), 0.3), ((0.6, -0.5, 0.1), -0.8), ((0.9, 0.0, 0.6), 0.0)]
)
def test_paddle_at_speed_moves_the_ball_point_along_the_normal(ball, angle):
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=ball, contact_angle=angle, speed=0.5)
    choice = choose_contact(problem)
    np.testing.assert_array_equal(choice.q, problem.q_contact)
    velocity = _ball_point_jacobian(robot, choice.q) @ choice.qd
    np.testing.assert_allclose(velocity, 0.5 * problem.normal, rtol=0, atol=1e-6)
    # The normal is held still at contact, as the time-optimal strike planner does.
    np.testing.assert_allclose(robot.jacobian(choice.q)[3:] @ choice.qd, 0.0, atol=1e-9)
    np.testing.assert_allclose(choice.qd, paddle_contact_velocity(problem), atol=1e-9)
    ratio = float(np.abs(choice.qd / robot.limits.velocity).max())
    np.testing.assert_allclose(choice.ratio, ratio, rtol=1e-12)
    np.testing.assert_allclose(choice.max_speed * choice.ratio, 0.5, rtol=1e-12)


def test_too_fast_paddle_strike_names_the_joint():
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=(1.0, 0.3, 0.4), contact_angle=0.3, speed=3.0)
    with pytest.raises(InfeasibleError) as info:
        choose_contact(problem)
    error = info.value
    assert error.limit == "velocity" and error.joint in robot.joint_names
    assert error.required > error.allowed
    slower = problems.PaddleStrike(
        robot, ball=(1.0, 0.3, 0.4), contact_angle=0.3, speed=0.999 * error.max_speed
    )
    assert choose_contact(slower).ratio == pytest.approx(0.999, rel=1e-9)


def test_stopping_speeds_leave_room_to_start_and_stop_on_both_sides():
    limits = get_robot("paddle4").limits  # J1, J3 in [0, 1] m; J2 in [-pi, pi], J4 in [-pi/2, pi/2]
    q = np.array([0.3, 3.0, 1.0, 0.0])
    room = np.array([0.3, np.pi - 3.0, 0.0, np.pi / 2])  # to the nearer limit
    expected = np.sqrt(2.0 * limits.acceleration * room)
    np.testing.assert_allclose(stopping_speeds(limits, q), expected, rtol=1e-12)
    # A joint on its limit cannot pass it moving; halving the room takes v by sqrt(2).
    assert stopping_speeds(limits, q)[2] == 0.0
    nearer = stopping_speeds(limits, [0.15, 3.0, 1.0, 0.0])[0]
    assert nearer == pytest.approx(expected[0] / np.sqrt(2.0), rel=1e-12)
    with pytest.raises(InvalidInputError):
        stopping_speeds(limits, [0.3, 0.0])


def test_paddle_contact_without_room_to_pass_it_is_refused_with_the_joint():
    # Found by a seeded random probe: the ball sits where J3 (the arm's extension) is 29 mm
    # from its upper limit at contact; the NLP found the strike infeasible after 77
    # iterations and said only "dynamics". No motion from rest to rest can pass a joint at
    # speed v with less than v^2 / (2 a) of room on either side.
    robot = get_robot("paddle4")
    ball, angle = (1.08197713, -0.72308109, 0.24624905), 0.5057469237104932
    problem = problems.PaddleStrike(robot, ball=ball, contact_angle=angle, speed=1.5)
    with pytest.raises(InfeasibleError) as info:
        choose_contact(problem)
    error = info.value
    q = np.asarray(problem.q_contact)
    assert (error.limit, error.joint, error.found_by) == ("position", "J3", CONTACT_CHOICE)
    assert error.allowed == pytest.approx(1.0 - q[2], rel=1e-12) and error.required > error.allowed
    assert "J3 is 0.02909 m from its upper limit" in str(error)
    # The fastest speed, from an independent LP over the ball point's velocity rows (the
    # paddle may turn) with each joint held to the speed its room and acceleration allow.
    limits = problem.limits
    room = np.minimum(q - limits.lower, limits.upper - q)
    allowed = np.minimum(limits.velocity, np.sqrt(2.0 * limits.acceleration * room))
    reference = 1.0 / _by_linprog(_ball_point_jacobian(robot, q), problem.normal, allowed)
    assert error.max_speed == pytest.approx(reference, rel=1e-5)
    assert 1.4 < error.max_speed < 1.5
    slower = dataclasses.replace(problem, speed=0.999 * error.max_speed)
    assert choose_contact(slower).q == pytest.approx(q)


# --------------------------------------------------------------------------- bad input


def test_choose_contact_rejects_other_problems_and_bad_settings():
    with pytest.raises(InvalidInputError, match="PickAndPlace") as info:
        choose_contact(problems.youbot_two_blocks())
    assert info.value.name == "problem"
    problem = problems.PaddleStrike(get_robot("paddle4"), ball=(1.0, 0.3, 0.4))
    for kwargs, name in (
        ({"candidates": 0}, "candidates"),
        ({"candidates": 2.5}, "candidates"),
        ({"seed": -1}, "seed"),
        ({"margin": 1.0}, "margin"),
        ({"margin": -0.1}, "margin"),
    ):
        with pytest.raises(InvalidInputError) as info:
            choose_contact(problem, **kwargs)
        assert info.value.name == name


def test_contact_choices_are_distinct_branches_led_by_the_chosen_one():
    problem = problems.sawyer_pool_shot(
        1.0, (0.770755805063373, 0.11771877321136866, -0.04053151295117215), 6.371000264362529
    )
    choices = contact_choices(problem, 4)
    assert len(choices) == 4
    np.testing.assert_array_equal(choices[0].q, choose_contact(problem).q)
    robot = problem.robot
    for choice in choices:
        assert choice.ratio <= 1.0
        np.testing.assert_allclose(robot.tool_position(choice.q), problem.contact_point, atol=1e-6)
        axis = robot.tool_pose(choice.q)[:3, 2]
        np.testing.assert_allclose(axis, problem.direction, atol=1e-6)
    for a, b in itertools.combinations(choices, 2):
        assert np.abs(a.q - b.q).max() > 0.1
    paddle = problems.seed_paddle_strike()
    assert len(contact_choices(paddle, 3)) == 1
    with pytest.raises(InvalidInputError, match="count"):
        contact_choices(problem, 0)


# ---------------------------------------------------------------- room to turn at the limits


def test_turn_estimate_matches_its_formula_and_ranks_cornered_contacts_last():
    from optraj.planners.strike.contact import _PoolSearch

    checked = 0
    for problem in _shots(6, speed=1.0, seed=31):
        choice = choose_contact(problem)
        search = _PoolSearch(problem)
        window = search.window(choice.q)
        np.testing.assert_allclose(
            problem.speed * window.turn, _turn_ratio(problem, choice.q), rtol=1e-7
        )
        # The choice has room to turn whenever some contact found had it.
        assert problem.speed * window.turn <= 1.0 or choice.ratio > 0.9
        checked += 1
    assert checked == 6


def test_a_joint_leaving_a_limit_it_sits_on_has_no_room_to_turn():
    from optraj.planners.strike.contact import _PoolSearch

    problem = next(_shots(1, speed=1.0, seed=32))
    search = _PoolSearch(problem)
    limits = problem.limits
    contact = (limits.lower + limits.upper) / 2
    entry, leave = contact.copy(), contact.copy()
    entry[0] = limits.lower[0]  # on its lower limit at the entry, moving up into the window
    contact[0] = limits.lower[0] + 0.01
    assert search._turn(entry, contact, leave) == math.inf
    entry[0] = limits.lower[0] + 0.011  # moving slowly down: the whole range behind it
    leave[0] = contact[0] + 0.005  # turned round inside the window, moving up fast
    rate = 0.005 / problem.follow_through
    expected = rate / math.sqrt(2 * limits.acceleration[0] * (limits.upper[0] - leave[0]))
    np.testing.assert_allclose(search._turn(entry, contact, leave), expected, rtol=1e-12)


def test_excluded_branches_are_left_out():
    problem = next(_shots(1, speed=1.0, seed=33))
    first = contact_choices(problem, 3)
    others = contact_choices(problem, 3, exclude=[first[0].q])
    for choice in others:
        assert np.abs(choice.q - first[0].q).max() > 0.1
    # The same search: the next branches of the first call come first.
    assert [c.q.tolist() for c in others[:2]] == [c.q.tolist() for c in first[1:]]
    # None excludes nothing; anything but configurations is named.
    assert [c.q.tolist() for c in contact_choices(problem, 3, exclude=None)] == [
        c.q.tolist() for c in first
    ]
    for bad, match in (
        (5, "exclude must be a sequence"),
        ([[0.0] * 3], r"exclude\[0\]"),
        (first[0].q, "put a single configuration in a list"),
    ):
        with pytest.raises(InvalidInputError, match=match):
            contact_choices(problem, 3, exclude=bad)
