import sweeps_support

from optraj.planners import registry
from optraj.sweeps.columns import COLUMNS
from optraj.sweeps.row import error_row, plan_row
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
