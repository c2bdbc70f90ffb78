"""The README's tour runs as written, and the errors it shows are the ones raised."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from viz_support import object_paths

from optraj import planners, robots
from optraj.errors import UnknownNameError, WorkspaceError

README = (Path(__file__).resolve().parents[1] / "README.md").read_text()


def test_readme_starts_with_the_two_setup_commands():
    first_block = re.search(r"```bash\n(.*?)```", README, re.S).group(1).splitlines()
    assert [line.split("#")[0].strip() for line in first_block] == ["make demo", "make test"]
    assert README.index("```bash") < README.index("optraj is a Python toolkit")


def test_tour_runs_and_its_comments_hold():
    tour = re.search(r"## A short tour\n\n```python\n(.*?)```", README, re.S).group(1)
    namespace: dict[str, object] = {}
    exec(compile(tour, "README.md", "exec"), namespace)
    paddle = namespace["paddle"]
    np.testing.assert_allclose(
        robots.paddle4_ik(paddle, [1.1, 0.8, 0.7]), [0.9, 0.3911, 0.9985, -0.3911], atol=1e-4
    )
    assert namespace["J"].shape == (6, 7)


def test_errors_shown_in_readme_are_verbatim():
    shown = dict(re.findall(r"^(\w+Error): (.*)$", README, re.M))
    paddle = robots.load("paddle4")
    with pytest.raises(WorkspaceError) as workspace:
        robots.paddle4_ik(paddle, ball=[1.2, 0.0, 0.3])
    assert shown["WorkspaceError"] == str(workspace.value)
    with pytest.raises(UnknownNameError) as unknown:
        robots.load("sawer")
    assert shown["UnknownNameError"] == str(unknown.value)


@pytest.mark.slow
def test_every_python_block_runs():
    blocks = re.findall(r"```python\n(.*?)```", README, re.S)
    assert len(blocks) >= 2
    namespace: dict[str, object] = {}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)
    report = namespace["report"]
    assert report.ok, report.summary()  # the pick-and-place the README shows passes
    # The tracking block's comments.
    pid, qp, run = namespace["pid"], namespace["qp"], namespace["run"]
    over = pid.metrics.violations["command"]
    assert over.worst == pytest.approx(1.51, abs=0.005) and over.joint == "right_j1"
    assert qp.metrics.violations["command"].worst <= 1.0
    assert run.metrics.strike.line_max == pytest.approx(4.1e-5, abs=3e-6)
    assert run.metrics.strike.speed_error_max == pytest.approx(0.00068, abs=2e-5)
    # The export block's comments.
    best, folder = namespace["best"], namespace["folder"]
    rows_written = (folder / "shot.csv").read_text().splitlines()
    assert len(rows_written) == 1 + (int(best.duration * 500) + 1) + 1  # header, k/500 s, end
    again = namespace["again"]
    np.testing.assert_allclose(again.sample(0.5).q, best.sample(0.5).q, atol=1e-6)
    assert [p["time_from_start"] for p in namespace["message"]["points"][:2]] == [
        {"sec": 0, "nanosec": 0},
        {"sec": 0, "nanosec": 10_000_000},
    ]
    assert "joint_names:" in namespace["yaml_text"]
    held = best.sample(best.duration + 1.0, hold=True)
    np.testing.assert_allclose(held.q, best.sample(best.duration).q)
    assert not held.qd.any()
    tg = namespace["tg"]
    assert tg.q.shape == tg.qd.shape == (101, 2) and tg.trajectory.duration == 2.0
    assert namespace["arrays"].trapezoidal(0.0, 1.0, 51, V=0.03).qd.max() == pytest.approx(0.03)
    np.testing.assert_allclose(namespace["moves"].arrive, [2.1, 4.3])
    # The viewer block: one page with the robot's cue, the table and the ball's path.
    page = namespace["page"].read_text()
    assert "MeshCat.Viewer" in page
    for name in ("robot/visuals/tool/cue", "scene/table/cloth", "scene/ball_path/0"):
        assert f"/meshcat/optraj/{name}" in object_paths(page), name
    # The scene block's comments.
    carried, task = namespace["carried"], namespace["task"]
    assert planners.check(carried, task)["clearance"].ok
    dragged = namespace["dragged"]["clearance"]
    assert not dragged.ok and dragged.value == pytest.approx(-0.0018, abs=5e-5)
    assert dragged.detail.startswith("tool/finger_left to block_0") and 8.2 < dragged.time < 8.4
    # The MuJoCo block's comments.
    ball, alone = namespace["ball"], namespace["alone"]
    assert ball.within and alone.within
    assert ball.heading_error == pytest.approx(0.052, abs=0.005)
    # The sweep block's comments.
    rows = namespace["rows"]
    assert len(rows) == 8 and [row["status"] for row in rows].count("planned") == 4
    assert all(row["status"] == "planned" for row in rows if row["speed"] == 0.5)
    assert rows[1]["binding_joint"] == "right_j1"
    assert rows[1]["max_speed"] == pytest.approx(1.26, abs=0.005)
    on_dask = namespace["on_dask"]  # the same sweep on a Dask LocalCluster
    assert [row["shot_id"] for row in on_dask] == [row["shot_id"] for row in rows]
    assert [row["status"] for row in on_dask] == [row["status"] for row in rows]
