"""Tests of planners.registry: the planners by kind of problem, made and extended."""

from __future__ import annotations

import pytest

from optraj import planners, problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners import registry


def test_every_kind_lists_planners_that_plan_its_problem_within_the_limits():
    made = {
        kind: [registry.make_planner(kind, name) for name in registry.planner_names(kind)]
        for kind in registry.KINDS
    }
    assert [type(p).__name__ for p in made["pool-shot"]] == [
        "PullBackStrike",
        *["ClassicStrike"] * 3,
        *["TimeOptimalStrike"] * 2,
        *["OptimalControl"] * 2,
    ]
    problem = problems.ece486_paddle_strike()
    for planner in made["paddle-strike"][:2]:  # the fast ones: judged by the checker
        assert planners.check(planner.plan(problem), problem).ok


def test_each_call_makes_a_new_planner_with_its_default_options():
    first = registry.make_planner("point-to-point", "optimal-control-jerk")
    second = registry.make_planner("point-to-point", "optimal-control-jerk")
    assert first is not second and first.name == second.name


def test_unknown_kinds_and_names_are_refused_with_the_known_ones():
    with pytest.raises(UnknownNameError, match="pool-shot"):
        registry.planner_names("pool")
    with pytest.raises(UnknownNameError, match="cubic"):
        registry.make_planner("pick-and-place", "toppra")


def test_a_registered_planner_joins_its_kind_and_the_command_line(monkeypatch):
    from optraj import cli

    kinds = {kind: dict(registry._REGISTRY[kind]) for kind in registry.KINDS}
    monkeypatch.setattr(registry, "_REGISTRY", kinds)
    registry.register_planner("point-to-point", "slow-cubic", planners.Cubic)
    assert registry.planner_names("point-to-point")[-1] == "slow-cubic"
    assert cli.PLANNERS["point-to-point"][-1] == "slow-cubic"
    assert isinstance(cli.make_planner("point-to-point", "slow-cubic"), planners.Cubic)
    with pytest.raises(InvalidInputError, match="already registered"):
        registry.register_planner("point-to-point", "cubic", planners.Cubic)
    with pytest.raises(InvalidInputError, match="lower-case words"):
        registry.register_planner("point-to-point", "Slow Cubic", planners.Cubic)
    with pytest.raises(InvalidInputError, match="callable"):
        registry.register_planner("point-to-point", "other", planners.Cubic())
    with pytest.raises(UnknownNameError):
        registry.register_planner("juggling", "cubic", planners.Cubic)


def test_settings_reach_the_planner_and_unknown_ones_are_refused():
    assert "contact" in registry.options("pool-shot", "cubic")
    assert "contact" not in registry.options("pool-shot", "pull-back")
    chosen = registry.make_planner("pool-shot", "toppra", contact="choose")
    assert chosen.contact == "choose"
    assert registry.make_planner("pool-shot", "toppra").contact == "problem"
    ocp = registry.make_planner("point-to-point", "optimal-control", intervals=7)
    assert ocp.intervals == 7 and ocp.objective == "time"
    with pytest.raises(InvalidInputError, match=r"takes no option 'contact'; its options are"):
        registry.make_planner("pool-shot", "pull-back", contact="choose")
    assert registry.options("pick-and-place", "cubic") == ()


def test_the_strike_benchmark_compares_every_pool_shot_planner(monkeypatch):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "strike.py"
    monkeypatch.syspath_prepend(str(path.parent))
    spec = importlib.util.spec_from_file_location("strike_benchmark", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    kinds = {kind: dict(registry._REGISTRY[kind]) for kind in registry.KINDS}
    monkeypatch.setattr(registry, "_REGISTRY", kinds)
    registry.register_planner("pool-shot", "slow-ruckig", planners.TimeOptimalStrike)
    pairs = module.planners_to_compare()
    assert len(pairs) == len(registry.planner_names("pool-shot"))
    label, planner = pairs[-1]  # a planner the table has no label for: its own name
    assert isinstance(planner, planners.TimeOptimalStrike) and planner.contact == "choose"
    assert label == planner.name
