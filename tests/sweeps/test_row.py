import pytest
import sweeps_support
from sweeps_support import velocity_ratio

from optraj.errors import InfeasibleError
from optraj.planners import registry
from optraj.sweeps.columns import COLUMNS, OUTCOME_COLUMNS
from optraj.sweeps.row import contact_columns, error_row, plan_row
from optraj.sweeps.shots import ShotSet

SHOTS = sweeps_support.SMALL.shots()


def test_planned_row():
    row = plan_row(registry.make_planner("pool-shot", "ruckig"), "ruckig", SHOTS[0])
    assert list(row) == list(COLUMNS)
    assert row["status"] == "planned" and row["planner"] == "ruckig"
    assert (row["ball_x"], row["ball_y"], row["ball_z"]) == SHOTS[0].ball
    assert row["heading"] == 0.0 and row["speed"] == 0.3
    assert row["motion_time"] > 0.0 and row["plan_time"] > 0.0
    assert row["check_ok"] is True
    assert row["error_type"] is None and row["error_message"] is None
    assert row["kind"] == "pool-shot" and 0.0 < row["contact_search_time"] < row["plan_time"]
    assert all(row[name] is None for name in OUTCOME_COLUMNS)  # not tracked


def test_planned_row_gives_the_fastest_speed_at_the_chosen_contact():
    shot = SHOTS[0]
    row = plan_row(registry.make_planner("pool-shot", "ruckig"), "ruckig", shot)
    fastest = row["max_speed"]
    assert row["binding_quantity"] == "velocity" and row["binding_joint"].startswith("right_j")
    assert shot.speed < fastest < 3.0
    # A plan from that contact needs at least speed / fastest of some velocity limit on its
    # strike line: no joint velocity giving the line's motion needs less.
    problem = shot.problem()
    plan = registry.make_planner("pool-shot", "ruckig", contact="choose").plan(problem)
    strike = plan.phase("strike")
    ratio = velocity_ratio(plan, problem.limits, strike.t_start, strike.t_end)
    assert ratio >= shot.speed / fastest * (1.0 - 1e-6)
    # And no contact makes the shot a little faster than that: the problem's own contact, as
    # ruckig plans it, breaks a velocity limit on the line.
    over = ShotSet(x=shot.ball[:1] * 2, y=shot.ball[1:2] * 2, grid=(1, 1), speeds=(1.03 * fastest,))
    refused = plan_row(registry.make_planner("pool-shot", "ruckig"), "ruckig", over[0])
    assert refused["status"] == "refused" and refused["error_type"] == "InfeasibleError"


def test_contact_columns_are_none_when_no_contact_is_fast_enough():
    fast = ShotSet(x=(0.7, 0.7), y=(0.0, 0.0), grid=(1, 1), speeds=(3.0,))[0].problem()
    columns = contact_columns(fast)
    assert columns["contact_search_time"] > 0.0
    assert {columns[k] for k in ("max_speed", "binding_joint", "binding_quantity")} == {None}


def test_refused_row_names_the_binding_joint_and_quantity():
    planner = registry.make_planner("pool-shot", "ruckig", contact="choose")
    fast = ShotSet(x=(0.7, 0.7), y=(0.0, 0.0), grid=(1, 1), speeds=(3.0,))[0]
    row = plan_row(planner, "ruckig", fast)  # over the velocity limits at any contact
    assert row["status"] == "refused" and row["error_type"] == "InfeasibleError"
    assert row["binding_joint"] == "right_j1" and row["binding_quantity"] == "velocity"
    assert 0.0 < row["max_speed"] < 3.0
    assert "3 m/s" in row["error_message"] and row["motion_time"] is None


def test_unreachable_ball_is_refused():
    far = ShotSet(x=(3.0, 3.0), y=(0.0, 0.0), grid=(1, 1))[0]
    row = plan_row(registry.make_planner("pool-shot", "cubic"), "cubic", far)
    assert row["status"] == "refused" and row["error_type"] == "UnreachableError"
    # The problem cannot be built, so there is no contact search and no fastest speed.
    assert row["max_speed"] is None and row["binding_joint"] is None
    assert row["binding_quantity"] is None and row["contact_search_time"] is None


def test_a_refusal_keeps_its_own_binding_limit():
    fast = ShotSet(x=(0.7, 0.7), y=(0.0, 0.0), grid=(1, 1), speeds=(3.0,))[0]
    planner = registry.make_planner("pool-shot", "ruckig")  # the problem's contact
    with pytest.raises(InfeasibleError) as info:
        planner.plan(fast.problem())
    error = info.value
    row = plan_row(planner, "ruckig", fast)
    assert row["status"] == "refused" and row["error_message"] == str(error)
    found = (row["binding_joint"], row["binding_quantity"], row["max_speed"])
    assert found == (error.joint, error.limit, error.max_speed)


def test_any_exception_is_a_failed_row():
    row = plan_row(sweeps_support.Raising(), "test-raise", SHOTS[0])
    assert row["status"] == "failed" and row["error_type"] == "RuntimeError"
    assert row["error_message"] == "forced failure"


def test_a_hang_is_a_timed_out_row():
    row = plan_row(sweeps_support.Sleeping(), "test-sleep", SHOTS[0], seconds=0.2)
    assert row["status"] == "timed out" and row["error_type"] == "ShotTimeout"
    assert 0.2 <= row["plan_time"] < 2.0


def test_error_row():
    row = error_row(SHOTS[0], "cubic", "failed", "WorkerDied", "gone")
    assert row["shot_id"] == SHOTS[0].shot_id and row["status"] == "failed"
    assert row["plan_time"] is None
