"""Tests of optraj.errors: one root, data-carrying subclasses, messages that name values."""

from __future__ import annotations

import pickle

import pytest

import optraj
from optraj import errors


def test_every_error_derives_from_the_root_and_is_exported():
    for name in errors.__all__:
        cls = getattr(errors, name)
        root = optraj.OptrajWarning if name.endswith("Warning") else optraj.OptrajError
        assert issubclass(cls, root)
        assert getattr(optraj, name) is cls
    assert set(optraj.__all__) == set(errors.__all__)


def test_unknown_name_lists_known_and_suggests():
    exc = errors.UnknownNameError("robot", "sawer", ["paddle4", "sawyer", "youbot"])
    assert (
        str(exc) == "unknown robot 'sawer'; known: paddle4, sawyer, youbot (did you mean 'sawyer'?)"
    )
    assert isinstance(exc, LookupError)
    assert exc.known == ("paddle4", "sawyer", "youbot")


def test_joint_limit_error_names_joint_value_and_limit():
    exc = errors.JointLimitError("J4", 1.9, -1.5708, 1.5708, unit="rad", context="IK")
    assert str(exc) == (
        "IK: joint 'J4' position 1.9 rad is above the upper limit 1.5708 "
        "(limits [-1.5708, 1.5708] rad)"
    )
    low = errors.JointLimitError("J1", -0.2, 0.0, 1.0, unit="m")
    assert "below the lower limit 0" in str(low)
    assert (low.joint, low.value, low.lower, low.upper) == ("J1", -0.2, 0.0, 1.0)


def test_workspace_error_names_the_broken_bound():
    exc = errors.WorkspaceError((1.2, 0.0, 0.3), "x", 1.2, 0.3, 1.1)
    assert "x = 1.2 m breaks the bound x <= 1.1 m" in str(exc)
    assert errors.WorkspaceError((0.5, -0.9, 0.3), "y", -0.9, -0.8, 0.8).lower == -0.8
    assert "y >= -0.8 m" in str(errors.WorkspaceError((0.5, -0.9, 0.3), "y", -0.9, -0.8, 0.8))


def test_missing_dependency_names_package_and_extra():
    exc = errors.MissingDependencyError("example-robot-data", "examples", "robots.load('panda')")
    assert isinstance(exc, ImportError)
    assert "pip install 'optraj[examples]'" in str(exc)
    assert exc.package == "example-robot-data"


def test_solver_error_carries_status_and_iterations():
    exc = errors.SolverError("ipopt", "Maximum_Iterations_Exceeded", iterations=3000)
    assert (
        str(exc)
        == "solver 'ipopt' failed with status 'Maximum_Iterations_Exceeded' after 3000 iterations"
    )
    assert exc.iterations == 3000


def test_infeasible_and_unreachable_carry_data():
    exc = errors.InfeasibleError(
        "too fast", limit="velocity", joint="right_j4", required=4.1, allowed=3.49
    )
    assert (exc.limit, exc.joint, exc.required, exc.allowed) == ("velocity", "right_j4", 4.1, 3.49)
    unreachable = errors.UnreachableError(
        "no", position_error=0.25, orientation_error=0.0, attempts=3
    )
    assert "best of 3 attempts: position error 0.25 m" in str(unreachable)


def test_invalid_input_is_a_value_error():
    with pytest.raises(ValueError, match="bad"):
        raise errors.InvalidInputError("bad", name="x", value=1)


def test_path_jump_error_names_time_joint_and_size():
    exc = errors.PathJumpError(0.42, "right_j5", 1.3, 0.1)
    assert "t = 0.42 s: joint 'right_j5' changes by 1.3" in str(exc)
    assert (exc.time, exc.joint, exc.jump, exc.threshold) == (0.42, "right_j5", 1.3, 0.1)
    assert issubclass(errors.PathJumpWarning, UserWarning)


def test_collision_error_names_the_pair_and_the_depth():
    exc = errors.CollisionError("tool/finger_left", "block_1", -0.0031, what="goal")
    text = str(exc)
    assert "'tool/finger_left'" in text and "'block_1'" in text and "3.1 mm" in text
    assert text.startswith("goal is in collision")
    assert (exc.first, exc.second, exc.distance, exc.point) == (
        "tool/finger_left",
        "block_1",
        -0.0031,
        None,
    )


@pytest.mark.parametrize(
    "error",
    [
        errors.InvalidInputError("speed must be >= 0 m/s, got -1 m/s", name="speed", value=-1.0),
        errors.UnknownNameError("robot", "sawer", ["paddle4", "sawyer"]),
        errors.MissingDependencyError("mujoco", "sim", "the MuJoCo plant"),
        errors.JointLimitError("J4", 1.9, -1.5708, 1.5708, unit="rad", context="IK"),
        errors.WorkspaceError((2.0, 0.0, 0.5), "x", 2.0, -1.0, 1.0),
        errors.UnreachableError("no IK", position_error=0.1, orientation_error=0.0, attempts=4),
        errors.InfeasibleError(
            "too fast",
            limit="velocity",
            joint="J1",
            required=3.0,
            allowed=2.0,
            max_speed=0.8,
            found_by=errors.CONTACT_CHOICE,
        ),
        errors.SolverError("ipopt", "Infeasible_Problem_Detected", iterations=9, detail="why"),
        errors.CompilerError("gcc", "not found"),
        errors.PathJumpError(0.5, "J2", 0.8, 0.1),
        errors.CollisionError("link_3", "block_0", -0.004, what="pick 0", point=(0.2, 0.1, 0.0)),
    ],
    ids=lambda error: type(error).__name__,
)
def test_errors_pickle_with_their_message_and_data(error):
    error.extra = 1.25  # attributes set after construction travel too
    copy = pickle.loads(pickle.dumps(error))
    assert type(copy) is type(error)
    assert str(copy) == str(error) and copy.args == error.args
    assert vars(copy) == vars(error)
    if isinstance(error, ImportError):
        assert copy.msg == error.msg


def test_the_error_catalogue_documents_every_error_and_nothing_else():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "errors.md").read_text()
    headings = [line[3:].strip() for line in text.splitlines() if line.startswith("## ")]
    assert sorted(headings) == sorted(errors.__all__)
    for name in headings:  # each entry says when it is raised and, for errors, what to do
        section = text.split(f"## {name}\n", 1)[1].split("\n## ", 1)[0]
        assert len(section.split()) >= 12, name
        if not name.endswith("Warning") and name != "OptrajError":
            assert "What to do:" in section, name
