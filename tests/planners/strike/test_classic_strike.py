"""Tests of planners.strike.classic_strike: cubic, quintic and LSPB pool strikes, by the checker."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.checker import check
from optraj.planners.profiles.time_scaling import cubic_coefficients, quintic_coefficients
from optraj.planners.strike.classic_strike import PROFILES, ClassicStrike, shortest_duration
from optraj.planners.trajectory import Trajectory

STRIKE = ("strike window", "strike position", "strike speed", "strike axis", "contact")
BASIC = ("position", "velocity", "acceleration")
#: The limits each profile keeps (a cubic's acceleration jumps at its ends: jerk unbounded).
KEPT = {"cubic": BASIC, "quintic": (*BASIC, "jerk")}


def _shots(count: int, speed: float):
    rng = np.random.default_rng(7)
    for _ in range(count):
        ball = (rng.uniform(0.65, 0.85), rng.uniform(-0.05, 0.3), rng.uniform(-0.1, 0.0))
        yield problems.sawyer_pool_shot(speed, ball, heading_deg=rng.uniform(-20.0, 20.0))


@pytest.fixture(scope="module")
def shots():
    return list(_shots(8, speed=0.5))


@pytest.fixture(scope="module")
def planned(shots):
    """(problem, cubic trajectory, quintic trajectory or None) of every shot the cubic plans."""
    result = []
    for problem in shots:
        try:
            cubic = ClassicStrike("cubic").plan(problem)
        except InfeasibleError as exc:
            assert exc.limit and exc.joint is not None  # names what binds
            continue
        try:
            quintic = ClassicStrike("quintic").plan(problem)
        except InfeasibleError as exc:
            assert exc.joint is not None and exc.required > exc.allowed
            quintic = None
        result.append((problem, cubic, quintic))
    return result


@pytest.mark.slow
def test_cubic_and_quintic_strikes_pass_the_checker(planned):
    assert len(planned) >= 6
    assert sum(quintic is not None for _, _, quintic in planned) >= 4
    for problem, cubic, quintic in planned:
        for profile, traj in (("cubic", cubic), ("quintic", quintic)):
            if traj is None:
                continue
            assert [p.name for p in traj.phases] == ["approach", "strike", "stop"]
            assert traj.metadata["planner"] == f"{profile} strike"
            report = check(traj, problem, quantities=KEPT[profile])
            assert report.ok, report.summary()
            assert all(report[name].ok for name in STRIKE)
        # The cubic cannot match the line's acceleration at the entry: its jerk is unbounded.
        assert check(cubic, problem, quantities=("jerk",))["jerk"].value == np.inf


def _approach_coefficients(profile, traj, duration):
    """The approach of ``traj`` rebuilt in closed form with another duration."""
    entry = traj.sample(traj.phase("strike").t_start)
    q0 = traj.sample(0.0).q
    zeros = np.zeros_like(q0)
    if profile == "cubic":
        return cubic_coefficients(q0, entry.q, duration, zeros, entry.qd)
    return quintic_coefficients(q0, entry.q, duration, zeros, entry.qd, zeros, entry.qdd)


def _stop_coefficients(profile, traj, duration):
    """The stop of ``traj`` rebuilt in closed form with another duration."""
    state = traj.sample(traj.phase("stop").t_start)
    zeros = np.zeros_like(state.q)
    if profile == "cubic":
        q_end = state.q + 0.5 * duration * state.qd
        return cubic_coefficients(state.q, q_end, duration, state.qd, zeros)
    q_end = state.q + 0.5 * duration * state.qd + duration**2 / 12.0 * state.qdd
    return quintic_coefficients(state.q, q_end, duration, state.qd, zeros, state.qdd, zeros)


@pytest.mark.parametrize("profile", ["cubic", "quintic"])
@pytest.mark.parametrize("piece", ["approach", "stop"])
def test_approach_and_stop_are_the_shortest_within_the_limits(planned, profile, piece):
    rebuild = _approach_coefficients if piece == "approach" else _stop_coefficients
    judged = 0
    for problem, cubic, quintic in planned[:4]:
        traj = cubic if profile == "cubic" else quintic
        if traj is None:
            continue
        judged += 1
        duration = traj.phase(piece).duration
        for factor, passes in ((1.0, True), (0.99, False)):
            coeffs = rebuild(profile, traj, factor * duration)
            alone = Trajectory([0.0, factor * duration], coeffs[None])
            report = check(alone, problem.robot, quantities=KEPT[profile])
            assert report.ok == passes, (factor, report.summary())
    assert judged >= 2


def test_cubic_stop_is_a_constant_deceleration_at_the_limit(planned):
    # Analytic reference: from qd to rest in T at constant deceleration qd / T, so the
    # shortest T is max_j |qd_j| / a_max_j.
    for problem, cubic, _ in planned[:4]:
        stop = cubic.phase("stop")
        qd = cubic.sample(stop.t_start).qd
        expected = np.max(np.abs(qd) / problem.limits.acceleration)
        np.testing.assert_allclose(stop.duration, expected, rtol=1e-5)
        np.testing.assert_allclose(cubic.sample(cubic.duration).qd, 0.0, atol=1e-12)


def test_lspb_enters_the_line_with_a_velocity_jump(shots):
    problem = shots[0]
    traj = ClassicStrike("lspb").plan(problem)
    assert [p.name for p in traj.phases] == ["approach", "strike", "stop"]
    report = check(traj, problem, quantities=BASIC)
    assert report["position"].ok and report["velocity"].ok, report.summary()
    assert all(report[name].ok for name in STRIKE), report.summary()
    acceleration = report["acceleration"]
    assert acceleration.value == np.inf and not report.ok
    assert "velocity jumps" in acceleration.detail
    # The worst of the jumps is reported (entry or exit); the entry's is there either way.
    entry, exit_time = traj.phase("strike").t_start, traj.phase("strike").t_end
    assert min(abs(acceleration.time - entry), abs(acceleration.time - exit_time)) < 1e-9
    before, after = traj.sample(entry - 1e-9).qd, traj.sample(entry).qd
    np.testing.assert_allclose(before, 0.0, atol=1e-6)
    np.testing.assert_allclose(np.max(np.abs(after)), traj.metadata["entry_velocity_jump"])
    assert traj.metadata["entry_velocity_jump"] > 0.0
    assert traj.metadata["exit_velocity_jump"] > 0.0


def test_a_strike_line_beyond_the_limits_is_infeasible_and_says_where():
    problem = problems.sawyer_pool_shot(speed=3.0)
    for profile in PROFILES:
        with pytest.raises(InfeasibleError, match="the strike line at 3 m/s needs joint") as info:
            ClassicStrike(profile).plan(problem)
        exc = info.value
        assert exc.limit in ("velocity", "acceleration", "jerk")
        assert exc.joint in problem.limits.names
        assert exc.required > exc.allowed


def test_shortest_duration_against_brute_force_on_random_cubics():
    limits = problems.sawyer_pool_shot(0.5).limits
    rng = np.random.default_rng(11)
    for _ in range(20):
        q0 = rng.uniform(-1.0, 1.0, limits.n)
        q1 = rng.uniform(-1.0, 1.0, limits.n)
        v1 = rng.uniform(-0.5, 0.5, limits.n) * limits.velocity

        def coefficients(duration, q0=q0, q1=q1, v1=v1):
            return cubic_coefficients(q0, q1, duration, 0.0, v1)

        duration = shortest_duration(coefficients, limits)
        # Brute force: the densely checked cubic fits at T and breaks a limit 1 % sooner.
        for factor, passes in ((1.0, True), (0.99, False)):
            alone = Trajectory([0.0, factor * duration], coefficients(factor * duration)[None])
            worst = max(
                np.max(np.abs(alone.sample(alone.times(20000)).qd) / limits.velocity),
                np.max(np.abs(alone.sample(alone.times(20000)).qdd) / limits.acceleration),
            )
            assert (worst <= 1.0 + 1e-6) == passes, (factor, worst)


def test_shortest_duration_names_the_binding_joint():
    limits = problems.sawyer_pool_shot(0.5).limits
    too_fast = 2.0 * limits.velocity

    def coefficients(duration):
        return cubic_coefficients(np.zeros(limits.n), np.ones(limits.n), duration, 0.0, too_fast)

    with pytest.raises(InfeasibleError, match="no cubic approach") as info:
        shortest_duration(coefficients, limits, what="cubic approach")
    assert info.value.limit == "velocity"
    assert info.value.required > info.value.allowed


def test_bad_inputs_raise_typed_errors():
    with pytest.raises(UnknownNameError, match="known: cubic, quintic, lspb") as info:
        ClassicStrike("trapezoid")  # type: ignore[arg-type]
    assert info.value.name == "trapezoid" and info.value.kind == "profile"
    with pytest.raises(InvalidInputError, match="samples"):
        ClassicStrike(samples=2)
    with pytest.raises(InvalidInputError, match="PoolStrike"):
        ClassicStrike().plan(problems.ece486_paddle_strike())  # type: ignore[arg-type]
    assert ClassicStrike("quintic").name == "quintic strike"


def test_sample_count_has_an_upper_bound():
    # issue 32, defect 7/6: one IK solve per sample; a count of 10**7 ran for hours
    with pytest.raises(InvalidInputError, match="samples must be an integer <= 100000"):
        ClassicStrike(samples=10**7)
