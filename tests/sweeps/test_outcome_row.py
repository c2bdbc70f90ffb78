import math
import time

from sweeps_support import SMALL

from optraj.planners import registry
from optraj.sweeps import OUTCOME_COLUMNS, PaddleShotSet
from optraj.sweeps import outcome_row as outcome_module
from optraj.sweeps.row import plan_row

RUCKIG = registry.make_planner("pool-shot", "ruckig")


def test_a_tracked_pool_shot_is_judged_by_the_ball():
    row = plan_row(RUCKIG, "ruckig", SMALL[0], outcome=True)  # 0.3 m/s, well within reach
    assert row["status"] == "planned" and row["outcome_error"] is None
    assert row["hit"] is True and row["on_target"] is True
    assert abs(row["heading_error"]) < 0.5 and abs(row["speed_error"]) < 0.02
    assert row["outcome_time"] > 0.0 and row["plan_time"] > 0.0


def test_an_error_in_the_outcome_keeps_the_planned_row():
    # A paddle arriving at rest sends no ball: physics.outcome refuses to judge it.
    shot = PaddleShotSet(x=(0.8, 0.8), y=(0.1, 0.1), grid=(1, 1, 1), speeds=(0.0,))[0]
    planner = registry.make_planner("paddle-strike", "ruckig")
    row = plan_row(planner, "ruckig", shot, outcome=True)
    assert row["status"] == "planned" and row["check_ok"] is True
    assert row["error_type"] is None and row["motion_time"] > 0.0
    assert row["outcome_error"].startswith("InvalidInputError: a paddle strike with speed 0")
    assert [row[k] for k in ("hit", "heading_error", "speed_error", "on_target")] == [None] * 4
    assert row["outcome_time"] > 0.0


def test_the_time_limit_stops_the_outcome_not_the_plan(monkeypatch):
    monkeypatch.setattr(outcome_module, "track", lambda trajectory, problem: time.sleep(30.0))
    start = time.monotonic()
    row = plan_row(RUCKIG, "ruckig", SMALL[0], seconds=1.5, outcome=True)
    assert time.monotonic() - start < 5.0
    assert row["status"] == "planned" and row["hit"] is None
    assert row["outcome_error"] == (
        "ShotTimeout: the shot ran past the time limit of 1.5 s during its outcome"
    )


def test_outcome_columns_missed_ball_is_infinite(monkeypatch):
    class Missed:
        hit, heading_error, speed_error, within = False, math.inf, math.inf, False

    monkeypatch.setattr(outcome_module, "track", lambda trajectory, problem: Missed())
    columns = outcome_module.outcome_columns(None, None)
    assert set(columns) == set(OUTCOME_COLUMNS)
    assert columns["hit"] is False and columns["on_target"] is False
    assert columns["heading_error"] == math.inf and columns["outcome_error"] is None


def test_refused_shots_are_not_tracked():
    fast = [shot for shot in SMALL if shot.speed == 0.9][-1]
    row = plan_row(RUCKIG, "ruckig", fast, outcome=True)
    assert row["status"] == "refused"
    assert all(row[name] is None for name in OUTCOME_COLUMNS)
