import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import sweeps_support  # noqa: F401  # registers the misbehaving planners
from sweeps_support import SMALL, outcome

from optraj import sweeps
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.sweeps import read_rows


@pytest.mark.slow
def test_serial_and_two_processes_give_identical_rows(tmp_path):
    serial = sweeps.run(SMALL, planner="ruckig", workers=0, progress=False)
    pooled = sweeps.run(
        SMALL, planner="ruckig", workers=2, out=tmp_path / "m.jsonl", progress=False
    )
    assert len(serial) == len(SMALL) and outcome(serial) == outcome(pooled)
    assert [row["shot_id"] for row in pooled] == [shot.shot_id for shot in SMALL]
    written = read_rows(tmp_path / "m.jsonl")  # in the order the rows arrived
    assert outcome(written[shot.shot_id] for shot in SMALL) == outcome(pooled)


@pytest.mark.slow
def test_a_stopped_run_restarted_plans_every_shot_once(tmp_path):
    out = tmp_path / "m.jsonl"
    first = sweeps.run(SMALL, planner="ruckig", workers=0, out=out, max_shots=3, progress=False)
    assert len(first) == 3
    rest = sweeps.run(SMALL, planner="ruckig", workers=2, out=out, progress=False)
    assert [row["shot_id"] for row in rest] == [shot.shot_id for shot in SMALL]
    assert rest[:3] == first  # the rows already done are read back, not planned again
    ids = [json.loads(line)["shot_id"] for line in out.read_text().splitlines()]
    assert sorted(ids) == sorted(shot.shot_id for shot in SMALL)


@pytest.mark.slow
def test_a_killed_run_restarted_plans_every_shot_once(tmp_path):
    out = tmp_path / "m.jsonl"
    script = (
        "import sys, sweeps_support\n"
        "from optraj import sweeps\n"
        "from optraj.planners import registry\n"
        "registry.register_planner('pool-shot', 'test-slow', sweeps_support.Slow)\n"
        "sweeps.run(sweeps_support.SMALL, planner='test-slow', workers=0, out=sys.argv[1],"
        " progress=False)\n"
    )
    tests = str(Path(__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": tests + os.pathsep + os.environ.get("PYTHONPATH", "")}
    child = subprocess.Popen([sys.executable, "-c", script, str(out)], env=env)
    deadline = time.monotonic() + 60.0
    while len(read_rows(out)) < 2 and time.monotonic() < deadline:
        time.sleep(0.02)
    child.send_signal(signal.SIGKILL)
    child.wait()
    done = read_rows(out)
    assert 2 <= len(done) < len(SMALL)
    rows = sweeps.run(SMALL, planner="test-slow", workers=2, out=out, progress=False)
    assert [row["shot_id"] for row in rows] == [shot.shot_id for shot in SMALL]
    assert all(rows[i] == row for i, row in enumerate(done.values()))  # not planned again
    lines = [line for line in out.read_text().splitlines() if line.strip()]
    assert sorted(json.loads(line)["shot_id"] for line in lines) == sorted(
        shot.shot_id for shot in SMALL
    )
    serial = sweeps.run(SMALL, planner="ruckig", workers=0, progress=False)
    assert [r["status"] for r in rows] == [r["status"] for r in serial]


def test_a_file_of_another_planner_is_refused(tmp_path):
    out = tmp_path / "m.jsonl"
    sweeps.run(SMALL.shots()[:1], planner="cubic", workers=0, out=out, progress=False)
    with pytest.raises(InvalidInputError, match="holds rows of planner 'cubic', not 'ruckig'"):
        sweeps.run(SMALL, planner="ruckig", workers=0, out=out, progress=False)


@pytest.mark.slow
def test_raise_and_hang_become_rows_with_their_reason():
    shots = SMALL.shots()[:2]
    failed = sweeps.run(shots, planner="test-raise", workers=0, progress=False)
    hung = sweeps.run(shots, planner="test-sleep", workers=2, time_limit=0.3, progress=False)
    assert [(r["status"], r["error_type"]) for r in failed] == [("failed", "RuntimeError")] * 2
    assert [(r["status"], r["error_type"]) for r in hung] == [("timed out", "ShotTimeout")] * 2


def test_planner_options_reach_the_planner():
    fast = sweeps.ShotSet(x=(0.7, 0.7), y=(0.0, 0.0), grid=(1, 1), speeds=(3.0,))
    (row,) = sweeps.run(
        fast, planner="ruckig", options={"contact": "choose"}, workers=0, progress=False
    )
    assert row["max_speed"] is not None and row["binding_quantity"] == "velocity"


@pytest.mark.parametrize(
    ("settings", "error", "words"),
    [
        ({"planner": "nope"}, UnknownNameError, "nope"),
        ({"options": {"bogus": 1}}, InvalidInputError, "takes no option 'bogus'"),
        ({"workers": -1}, InvalidInputError, "workers must be an integer >= 0, got -1"),
        ({"time_limit": 0.0}, InvalidInputError, "time_limit must be > 0 s, got 0 s"),
        ({"chunk_size": 0}, InvalidInputError, "chunk_size must be an integer >= 1, got 0"),
        ({"max_shots": 1.5}, InvalidInputError, "max_shots must be an integer"),
        ({"progress": "yes"}, InvalidInputError, "progress must be True or False"),
    ],
)
def test_bad_settings_raise_typed_errors(settings, error, words):
    with pytest.raises(error) as info:
        sweeps.run(SMALL, **{"planner": "ruckig", "workers": 0, **settings})
    assert words in str(info.value)


def test_bad_shots_raise_typed_errors():
    with pytest.raises(InvalidInputError, match="iterable of Shot"):
        sweeps.run(3, planner="ruckig")
    with pytest.raises(InvalidInputError, match="Shot records"):
        sweeps.run([1, 2], planner="ruckig")
    shot = SMALL[0]
    with pytest.raises(InvalidInputError, match="given twice"):
        sweeps.run([shot, shot], planner="ruckig")
