"""Tests of planners.ocp.options."""

import casadi as ca
import pytest

from optraj.errors import InvalidInputError, MissingDependencyError, UnknownNameError
from optraj.planners.ocp.options import OBJECTIVES, SOLVERS, objective_weights, solver_name


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
