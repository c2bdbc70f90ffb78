"""Tests of planners.ocp.options."""

import casadi as ca
import pytest

from optraj.errors import InvalidInputError, MissingDependencyError, UnknownNameError
from optraj.planners.ocp.options import (
    OBJECTIVES,
    SOLVERS,
    checked_fraction,
    checked_intervals,
    checked_max_interval,
    checked_position_rows,
    checked_solver_options,
    checked_torque,
    objective_weights,
    solver_name,
)


def test_objective_weights_of_a_name_and_of_a_mapping():
    assert objective_weights("jerk") == {"jerk": 1.0}
    # Terms weighted 0 drop out; the weights are kept as given.
    assert objective_weights({"time": 2.0, "effort": 0.0, "jerk": 0.5}) == {
        "time": 2.0,
        "jerk": 0.5,
    }


@pytest.mark.parametrize(
    ("objective", "error"),
    [
        ("speed", UnknownNameError),
        ({}, InvalidInputError),
        ({"time": 0.0}, InvalidInputError),
        ({"time": -1.0}, InvalidInputError),
        ({"speed": 1.0}, UnknownNameError),
        (3, InvalidInputError),
    ],
)
def test_objective_weights_name_bad_input(objective, error):
    with pytest.raises(error):
        objective_weights(objective)


def test_solver_names_are_checked_against_the_list_and_the_installed_plugins():
    assert "time" in OBJECTIVES and SOLVERS[0] == "ipopt"
    assert solver_name("ipopt") == "ipopt"
    with pytest.raises(UnknownNameError):
        solver_name("fatrop")
    missing = [name for name in SOLVERS if not ca.has_nlpsol(name)]
    for name in missing:
        with pytest.raises(MissingDependencyError):
            solver_name(name)


def test_option_checks_pass_good_values_and_name_bad_ones():
    assert checked_solver_options(None) == {}
    assert checked_intervals({"move": 12, "segment 2": 3}) == {"move": 12, "segment 2": 3}
    assert checked_intervals(7) == 7 and checked_intervals(None) is None
    assert checked_max_interval(0.1) == 0.1
    assert checked_fraction("margin", 0.0) == 0.0
    assert checked_torque("auto") == "auto" and checked_position_rows(True) is True
    for check, value, name in (
        (checked_solver_options, [("tol", 1e-6)], "solver_options"),
        (checked_intervals, {"segment 0": 3}, "intervals"),
        (checked_max_interval, 1e-5, "max_interval"),
        (lambda value: checked_fraction("torque_margin", value), 0.5, "torque_margin"),
        (checked_torque, "yes", "torque"),
        (checked_position_rows, False, "position_rows"),
    ):
        with pytest.raises(InvalidInputError) as info:
            check(value)
        assert info.value.name == name
