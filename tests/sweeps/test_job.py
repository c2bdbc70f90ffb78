import pickle

import pytest
import sweeps_support
from sweeps_support import SMALL

from optraj.errors import InvalidInputError
from optraj.planners import registry
from optraj.sweeps import OUTCOME_COLUMNS, ShotJob


def test_a_job_plans_a_shot_and_pickles():
    job = ShotJob(registry.make_planner("pool-shot", "cubic"), "cubic", seconds=10.0)
    again = pickle.loads(pickle.dumps(job))
    assert again.name == "cubic" and again.seconds == 10.0 and again.outcome is False
    row = again.row(SMALL[0])
    assert row["planner"] == "cubic" and row["status"] == "planned"
    assert all(row[name] is None for name in OUTCOME_COLUMNS)


def test_error_row_names_the_planner():
    job = ShotJob(sweeps_support.Raising(), "test-raise")
    row = job.error_row(SMALL[1], "failed", "WorkerDied", "gone")
    assert (row["planner"], row["status"], row["error_message"]) == ("test-raise", "failed", "gone")
    assert job.row(SMALL[1])["error_message"] == "forced failure"


def test_outcome_must_be_a_flag():
    with pytest.raises(InvalidInputError, match="outcome must be True or False"):
        ShotJob(registry.make_planner("pool-shot", "cubic"), "cubic", outcome="yes")
