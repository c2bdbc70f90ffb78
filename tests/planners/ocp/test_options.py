"""Tests of planners.ocp.options."""

import casadi as ca
import pytest

from optraj.errors import InvalidInputError, MissingDependencyError, UnknownNameError
from optraj.planners.ocp import options


def test_objective_weights_of_a_name_and_of_a_mapping():
    assert options.objective_weights("jerk") == {"jerk": 1.0}
    # Terms weighted 0 drop out; the weights are kept as given.
    assert options.objective_weights({"time": 2.0, "effort": 0.0, "jerk": 0.5}) == {
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
        options.objective_weights(objective)


def test_solver_names_are_checked_against_the_list_and_the_installed_plugins():
    assert "time" in options.OBJECTIVES and options.SOLVERS[0] == "ipopt"
    assert options.solver_name("ipopt") == "ipopt"
    with pytest.raises(UnknownNameError):
        options.solver_name("fatrop")
    missing = [name for name in options.SOLVERS if not ca.has_nlpsol(name)]
    for name in missing:
        with pytest.raises(MissingDependencyError):
            options.solver_name(name)


def test_option_checks_pass_good_values_and_name_bad_ones():
    assert options.checked_solver_options(None) == {}
    assert options.checked_intervals({"move": 12, "segment 2": 3}) == {"move": 12, "segment 2": 3}
    assert options.checked_intervals(7) == 7 and options.checked_intervals(None) is None
    assert options.checked_max_interval(0.1) == 0.1
    assert options.checked_fraction("margin", 0.0) == 0.0
    assert options.checked_torque("auto") == "auto" and options.checked_position_rows(True) is True
    for check, value, name in (
        (options.checked_solver_options, [("tol", 1e-6)], "solver_options"),
        (options.checked_intervals, {"segment 0": 3}, "intervals"),
        (options.checked_max_interval, 1e-5, "max_interval"),
        (lambda value: options.checked_fraction("torque_margin", value), 0.5, "torque_margin"),
        (options.checked_torque, "yes", "torque"),
        (options.checked_position_rows, False, "position_rows"),
    ):
        with pytest.raises(InvalidInputError) as info:
            check(value)
        assert info.value.name == name
