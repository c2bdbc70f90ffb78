import sweeps_support
from sweeps_support import SMALL

from optraj.planners import registry
from optraj.sweeps.job import ShotJob
from optraj.sweeps.serial import run_serial

SHOTS = SMALL.shots()


def test_rows_come_in_the_order_of_the_shots():
    rows = []
    job = ShotJob(registry.make_planner("pool-shot", "cubic"), "cubic")
    run_serial(SHOTS[:3], job, rows.append)
    assert [row["shot_id"] for row in rows] == [shot.shot_id for shot in SHOTS[:3]]
    assert all(row["planner"] == "cubic" for row in rows)


def test_a_hang_is_stopped_at_the_time_limit():
    rows = []
    run_serial(SHOTS[:2], ShotJob(sweeps_support.Sleeping(), "test-sleep", 0.2), rows.append)
    assert [row["status"] for row in rows] == ["timed out", "timed out"]
