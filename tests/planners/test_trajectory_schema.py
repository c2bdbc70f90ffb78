"""Tests of planners.trajectory_schema: the shipped JSON Schema against what to_json writes."""

from __future__ import annotations

import copy
import json
import sys
import tomllib
from importlib import resources
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.planners.trajectory_schema import SCHEMA_FILE, load_schema, validate_trajectory_data

ROOT = Path(__file__).resolve().parents[2]


def _move() -> problems.PointToPoint:
    robot = get_robot("paddle4")
    middle = 0.5 * (robot.limits.lower + robot.limits.upper)
    return problems.PointToPoint(robot, middle, middle + 0.2 * (robot.limits.upper - middle))


def _waypoints() -> problems.Waypoints:
    move = _move()
    points = [move.q_start, 0.5 * (move.q_start + move.q_goal) + 0.05, move.q_goal]
    return problems.Waypoints(move.robot, np.array(points))


#: One plan of each planner family, cheap ones (paddle4, coarse grids).
PLANS = {
    "quintic": lambda: planners.Quintic().plan(_move()),
    "lspb": lambda: planners.LSPB().plan(_move()),
    "via points": lambda: planners.ViaPoints().plan(_waypoints()),
    "toppra": lambda: planners.Toppra(gridpoints=20).plan(_move()),
    "ruckig": lambda: planners.Ruckig().plan(_move()),
    "optimal control": lambda: planners.OptimalControl().plan(_move()),
    "strike": lambda: planners.PullBackStrike().plan(problems.sawyer_pool_shot(speed=1.0)),
}


def test_the_schema_is_draft_2020_12_and_ships_with_the_package():
    schema = load_schema()
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["properties"]["format"]["const"] == "optraj.trajectory/1"
    shipped = resources.files("optraj.planners").joinpath(SCHEMA_FILE)
    assert json.loads(shipped.read_text()) == schema
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "*.json" in data["tool"]["setuptools"]["package-data"]["optraj.planners.schema"]
    load_schema()["title"] = "changed"
    assert load_schema() == schema  # each call is a new copy


@pytest.mark.parametrize(
    "family",
    [pytest.param(name, marks=pytest.mark.slow) if name == "toppra" else name for name in PLANS],
)
def test_every_written_trajectory_follows_the_schema(family):
    traj = PLANS[family]()
    data = json.loads(traj.to_json())
    jsonschema.Draft202012Validator(load_schema()).validate(data)
    validate_trajectory_data(data)
    assert planners.Trajectory.from_dict(data).duration == traj.duration


def _good() -> dict:
    traj = planners.Trajectory.constant(
        [0.0, 1.0], 1.0, phases=[planners.Phase("hold", 0.0, 1.0)], metadata={"planner": "x"}
    )
    return json.loads(traj.to_json())


def _broken(change):
    data = copy.deepcopy(_good())
    change(data)
    return data


@pytest.mark.parametrize(
    ("change", "field", "rule"),
    [
        (lambda d: d.pop("breakpoints"), "(top level)", "'breakpoints' is a required property"),
        (lambda d: d.pop("format"), "(top level)", "'format' is a required property"),
        (lambda d: d.update(format="optraj.trajectory/2"), "format", "was expected"),
        (lambda d: d.update(breakpoints=[0, "1"]), "breakpoints/1", "is not of type 'number'"),
        (lambda d: d.update(breakpoints=[0]), "breakpoints", "is too short"),
        (lambda d: d.update(coefficients=[[[0.0, 1.0], 5.0]]), "coefficients/0/1",
         "not of type 'array'"),
        (lambda d: d["phases"][0].update(t_end="1"), "phases/0/t_end", "not of type 'number'"),
        (lambda d: d["phases"][0].pop("name"), "phases/0", "'name' is a required property"),
        (lambda d: d.update(joint_names=["a", 2]), "joint_names/1", "not of type 'string'"),
        (lambda d: d.update(metadata=[]), "metadata", "not of type 'object'"),
        (lambda d: d["metadata"].update(planner=3), "metadata/planner", "not of type 'string'"),
        (lambda d: d.update(extra=1), "(top level)", "Additional properties are not allowed"),
    ],
)  # fmt: skip
def test_a_broken_trajectory_breaks_the_schema(change, field, rule):
    data = _broken(change)
    assert not jsonschema.Draft202012Validator(load_schema()).is_valid(data)
    with pytest.raises(InvalidInputError, match=r"breaks the optraj\.trajectory/1 schema") as info:
        validate_trajectory_data(data)
    assert str(info.value).startswith(
        f"trajectory data breaks the optraj.trajectory/1 schema at {field}: "
    )
    assert rule in str(info.value)
    validate_trajectory_data(_good())  # the unbroken one passes


def test_without_jsonschema_validation_names_the_package(monkeypatch):
    monkeypatch.setitem(sys.modules, "jsonschema", None)  # import jsonschema then fails
    with pytest.raises(MissingDependencyError, match="needs the package 'jsonschema'"):
        validate_trajectory_data(_good())
