"""Tests of optraj.planners.time_optimal.toppra_passes: toppra's passes, the same numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest
import toppra.algorithm
from conftest import get_robot

from optraj.planners import Toppra
from optraj.planners.time_optimal import toppra_classes
from optraj.planners.time_optimal.toppra_problem import initial_scale

#: toppra's own parametrisation, which SeidelTOPPRA's must equal.
TOPPRAS_OWN = toppra.algorithm.TOPPRA.compute_parameterization


class _Failing:
    """A solver wrapper that answers NaN on chosen calls and passes the rest through."""

    def __init__(self, solver, failing):
        self._solver = solver
        self._failing = failing
        self.calls = 0

    def __getattr__(self, name):
        return getattr(self._solver, name)

    def solve_stagewise_optim(self, *args):
        self.calls += 1
        if self.calls in self._failing:
            return [math.nan] * self._solver.get_no_vars()
        return self._solver.solve_stagewise_optim(*args)


def _instance(robot_name, rng, failing=frozenset()):
    robot = get_robot(robot_name)
    waypoints = robot.random_configurations(int(rng.integers(2, 6)), rng)
    built = Toppra(gridpoints=int(rng.integers(10, 150))).build(waypoints, robot.limits)
    instance = toppra_classes.TOPPRA(
        built.constraints(initial_scale(built)), built.path.native, built.grid
    )
    instance.solver_wrapper = _Failing(instance.solver_wrapper, failing)
    return instance


def _outcome(parametrize, instance, sd_start, sd_end):
    result = parametrize(instance, sd_start, sd_end, return_data=True)
    data = instance.problem_data
    arrays = [None if x is None else np.asarray(x).tolist() for x in result]
    stored = getattr(data, "K", None)
    return arrays, data.return_code, None if stored is None else stored.tolist()


@pytest.mark.parametrize("robot_name", ["panda", "sawyer", "youbot"])
def test_the_passes_give_toppras_numbers_on_seeded_random_paths(robot_name):
    # Bit for bit: the same solver calls in the same order, with the same clamps.
    rng = np.random.default_rng(3506)
    for _ in range(12):
        ends = [(0.0, 0.0), (0.3, 0.0), (0.0, 0.5), (80.0, 0.0)][int(rng.integers(4))]
        seed = int(rng.integers(2**32))
        ours = _outcome(
            toppra_classes.TOPPRA.compute_parameterization,
            _instance(robot_name, np.random.default_rng(seed)),
            *ends,
        )
        theirs = _outcome(TOPPRAS_OWN, _instance(robot_name, np.random.default_rng(seed)), *ends)
        np.testing.assert_equal(ours, theirs)


def test_failed_stages_are_handled_as_toppra_handles_them():
    # NaN answers in the backward pass (uncontrollable) and in the forward pass (retries
    # with a lowered x, then giving up) take toppra's branches.
    rng = np.random.default_rng(3507)
    codes = set()
    for _ in range(40):
        seed = int(rng.integers(2**32))
        stages = _instance("panda", np.random.default_rng(seed)).solver_wrapper.get_no_stages()
        backward = 2 * stages
        if rng.random() < 0.3:
            failing = frozenset(int(k) for k in rng.integers(1, backward + 1, size=1))
        else:  # forward calls: some runs of more than toppra's ten retries
            first = backward + int(rng.integers(1, stages + 1))
            failing = frozenset(range(first, first + int(rng.integers(1, 14))))
        results = [
            _outcome(
                parametrize, _instance("panda", np.random.default_rng(seed), failing), 0.0, 0.0
            )
            for parametrize in (toppra_classes.TOPPRA.compute_parameterization, TOPPRAS_OWN)
        ]
        np.testing.assert_equal(results[0], results[1])  # NaN equals NaN here
        codes.add(results[0][1])
    codes_wanted = toppra.algorithm.ParameterizationReturnCode
    assert {codes_wanted.Ok, codes_wanted.ErrUnknown, codes_wanted.FailUncontrollable} <= codes


def test_negative_path_velocities_are_refused_as_toppra_refuses_them():
    instance = _instance("panda", np.random.default_rng(3508))
    with pytest.raises(toppra.exceptions.BadInputVelocities):
        instance.compute_parameterization(-1.0, 0.0)
