"""Tests of planners.time_optimal.ruckig_calculation: one calculator per thread, Ruckig's
errors as typed errors, a status its binding does not name."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import ruckig
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError, SolverError
from optraj.planners.time_optimal.ruckig_calculation import (
    _calculator,
    calculate,
    reused_input,
    ruckig_error,
    ruckig_input,
)
from optraj.planners.time_optimal.ruckig_move import state_to_state
from optraj.planners.time_optimal.ruckig_planner import Ruckig
from optraj.planners.time_optimal.ruckig_validation import SYNCHRONIZATIONS


def test_each_thread_has_its_own_ruckig_calculator():
    here = _calculator(7)
    with ThreadPoolExecutor(max_workers=1) as pool:
        there = pool.submit(_calculator, 7).result()
    assert here is _calculator(7) and there is not here


def test_plans_from_several_threads_equal_plans_from_one():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(3)
    moves = [
        problems.PointToPoint(robot, *robot.limits.sample(rng, 2), limits=robot.limits)
        for _ in range(200)
    ]
    planner = Ruckig()
    serial = [planner.plan(move) for move in moves]
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(planner.plan, moves))
    for one, other in zip(serial, threaded, strict=True):
        assert one.duration == other.duration
        np.testing.assert_array_equal(one.coefficients, other.coefficients)


def test_errors_raised_inside_ruckig_become_typed_errors():
    limits = get_robot("sawyer").limits
    inside = ruckig.RuckigError(
        "\n[ruckig] target velocity 1.5 of DoF 2 exceeds its maximum velocity limit 1.0."
    )
    error = ruckig_error(inside, limits)
    assert isinstance(error, InfeasibleError) and error.joint == "right_j2"
    assert "joint 'right_j2'" in str(error) and "DoF" not in str(error)
    error = ruckig_error(ruckig.RuckigError("[ruckig] error in step 1, dof: 0"), limits)
    assert isinstance(error, SolverError) and error.solver == "ruckig"


def test_a_duration_beyond_ruckigs_range_is_a_solver_error():
    limits = get_robot("paddle4").limits
    start, goal = np.zeros(4), np.array([0.5, 0.1, 0.2, 0.0])
    # Ruckig answers -101 (its duration range ends near 7.6e3 s), a status its Python
    # binding has no name for.
    with pytest.raises(SolverError, match="-101"):
        state_to_state(start, None, None, goal, None, None, limits, minimum_duration=1e4)


def _native_samples(native):
    """A Ruckig result's duration and its states at 17 instants, as floats."""
    times = np.linspace(0.0, native.duration, 17)
    return native.duration, [native.at_time(float(t)) for t in times]


def test_a_reused_input_gives_what_a_new_input_gives_over_a_seeded_random_sequence():
    # The reused input must forget what the previous move set: boundary states, options,
    # a minimum duration, and the limits of another limits object.
    robot = get_robot("panda")
    choices = [robot.limits, robot.limits.scaled(0.5), robot.limits.scaled(0.8, ("jerk",))]
    rng = np.random.default_rng(3509)
    synchronizations = list(SYNCHRONIZATIONS.values())
    for _ in range(120):
        limits = choices[int(rng.integers(len(choices)))]
        q0, q1 = limits.sample(rng, 2)
        states = None
        if rng.random() < 0.5:
            states = tuple(
                (0.1 * limits.velocity * rng.uniform(-1, 1, limits.n)).tolist() for _ in range(4)
            )
            states = (states[0], [0.0] * limits.n, states[2], [0.0] * limits.n)
        options = {
            "synchronization": synchronizations[int(rng.integers(3))],  # not "none"
            "minimum_duration": None if rng.random() < 0.6 else float(rng.uniform(0.5, 5.0)),
            "interface": ruckig.ControlInterface.Velocity
            if rng.random() < 0.2
            else ruckig.ControlInterface.Position,
        }
        fresh = calculate(ruckig_input(limits, q0, q1, states, **options), limits)
        reused = calculate(reused_input(limits, q0, q1, states, **options), limits)
        assert _native_samples(reused) == _native_samples(fresh)
