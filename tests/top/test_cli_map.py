"""Tests of ``optraj map``: a tiny sweep to a Parquet table, its heat maps, bad input."""

from __future__ import annotations

import io
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cli_support import error_line, refused

from optraj import sweeps
from optraj.cli import main
from optraj.cli_map import parse_grid, parse_numbers

pytest.importorskip("pyarrow")  # the sweeps extra, which make test installs

SWEEP = ["map", "sawyer", "--grid", "2x2", "--x", "0.7,0.8", "--y", "0,0.2", "--speeds",
         "0.3,0.9", "--planner", "cubic", "--workers", "0"]  # fmt: skip


def _run(argv: list[str]) -> tuple[int, str]:
    out = io.StringIO()
    return main(argv, out=out), out.getvalue()


@pytest.mark.slow
def test_a_sweep_writes_the_table_and_counts_each_status(tmp_path):
    table = tmp_path / "map.parquet"
    status, text = _run([*SWEEP, "--out", str(table)])
    assert status == 0
    rows = sweeps.read_parquet(table)
    assert len(rows) == 8 and {row["planner"] for row in rows} == {"cubic"}
    planned = sum(row["status"] == "planned" for row in rows)
    assert f"planned {planned}, refused {8 - planned}, failed 0, timed out 0" in text
    assert "8 shots (2x2 positions, headings 0 deg, speeds 0.3, 0.9 m/s)" in text
    assert f"table: {table} (8 rows)" in text


@pytest.mark.slow
def test_paddle4_strikes_are_swept_and_judged_by_the_ball(tmp_path):
    table = tmp_path / "paddle.jsonl"
    argv = ["map", "paddle4", "--grid", "2x1x1", "--x", "0.6,0.9", "--y", "0,0", "--speeds",
            "1.0", "--planner", "ruckig", "--workers", "0", "--outcome"]  # fmt: skip
    argv += ["--out", str(table)]
    status, text = _run(argv)
    assert status == 0, text
    rows = list(sweeps.read_rows(table).values())
    assert [row["kind"] for row in rows] == ["paddle-strike"] * 2
    assert all(row["status"] == "planned" and row["check_ok"] for row in rows)
    assert all(row["hit"] and row["on_target"] for row in rows)  # the ball left on its line
    assert all(row["max_speed"] > 1.0 for row in rows)


def test_z_and_a_three_axis_grid_are_for_paddle4_only(capsys, tmp_path):
    out = str(tmp_path / "m.jsonl")
    assert main(["map", "sawyer", "--z", "0.1,0.2", "--out", out]) == 2
    assert "--z is for paddle4's ball points" in error_line(capsys)
    assert main(["map", "sawyer", "--grid", "2x2x2", "--out", out]) == 2
    assert "--grid takes NXxNY" in error_line(capsys)
    assert main(["map", "paddle4", "--grid", "2x2", "--out", out]) == 2
    assert "--grid takes NXxNYxNZ" in error_line(capsys)


@pytest.mark.slow
def test_a_stopped_sweep_says_what_is_left_and_resumes(tmp_path):
    table = tmp_path / "map.parquet"
    status, text = _run([*SWEEP, "--out", str(table), "--max-shots", "3"])
    assert status == 0 and "5 shots left" in text and "(3 rows)" in text
    status, text = _run([*SWEEP, "--out", str(table)])
    assert status == 0 and "left" not in text
    ids = [row["shot_id"] for row in sweeps.read_parquet(table)]
    assert sorted(ids) == sorted(shot.shot_id for shot in sweeps.ShotSet(
        x=(0.7, 0.8), y=(0.0, 0.2), grid=(2, 2), speeds=(0.3, 0.9)))  # fmt: skip


def test_plot_writes_both_heat_maps(tmp_path):
    pytest.importorskip("matplotlib")
    table = tmp_path / "map.parquet"
    assert _run([*SWEEP, "--out", str(table)])[0] == 0
    status, text = _run(["map", "--plot", str(table), "--speed", "0.3"])
    assert status == 0
    for image in (tmp_path / "map.png", tmp_path / "map-motion-time.png"):
        assert image.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "motion time [s] at 0.3 m/s" in text
    status, _ = _run(["map", "--plot", str(table), "--image", str(tmp_path / "other.svg")])
    assert status == 0 and (tmp_path / "other-motion-time.svg").exists()


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["map"], "optraj map needs a robot to sweep"),
        (["map", "sawer"], "unknown robot 'sawer'"),
        ([*SWEEP, "--grid", "20by20"], "--grid takes NXxNY, ball positions along x and y, e.g. "
         "20x20; got '20by20'"),
        ([*SWEEP, "--speeds", "0.5,fast"], "--speeds takes numbers [m/s] separated by commas, "
         "e.g. 0.5,1.0; got '0.5,fast'"),
        ([*SWEEP, "--speeds", "0.5,0"], "speeds must be > 0 m/s, got 0 m/s"),
        ([*SWEEP, "--x", "0.7"], "--x takes two numbers FIRST,LAST [m]"),
        ([*SWEEP, "--samples", "4"], "give --grid (2x2) or --samples (4), not both"),
        ([*SWEEP, "--planner", "fastest"], "unknown planner for pool-shot 'fastest'"),
        ([*SWEEP, "--time-limit", "0"], "time_limit must be > 0 s, got 0 s"),
        ([*SWEEP, "--speed", "0.3"], "--image and --speed are for drawing a table"),
        (["map", "--plot", "none.parquet"], "no sweep rows in 'none.parquet'"),
        (["map", "sawyer", "--plot", "m.parquet"], "give no robot (got 'sawyer')"),
        (["map", "--plot", "m.parquet", "--image", "m.jpg"],
         "--image must end in .png, .pdf, .svg, got 'm.jpg'"),
        (["map", "sawyer", "--workers", "many"], "argument --workers: invalid int value: 'many'"),
    ],
)  # fmt: skip
def test_bad_arguments_exit_2_with_one_line_naming_the_value(
    argv, expected, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    line = refused(argv, capsys)
    assert line.startswith("optraj") and expected in line
    assert list(tmp_path.iterdir()) == []


def test_every_sweep_option_reaches_sweeps_run(monkeypatch, tmp_path):
    seen = {}

    def run(shots, planner, **settings):
        seen.update(shots=shots, planner=planner, **settings)
        return []

    monkeypatch.setattr(sweeps, "run", run)
    argv = ["map", "sawyer", "--samples", "5", "--seed", "3", "--headings=-10,10",
            "--scheduler", "tcp://10.0.0.1:8786", "--time-limit", "2.5", "--max-shots", "4",
            "--workers", "3", "--outcome", "--out", str(tmp_path / "m.jsonl")]  # fmt: skip
    status, text = _run(argv)
    assert status == 0 and "5 shots left" in text
    assert "5 shots (5 random positions, headings -10 to 10 deg, speeds 0.5 m/s)" in text
    assert seen["shots"] == sweeps.ShotSet(samples=5, seed=3, headings=(-10.0, 10.0))
    assert seen["planner"] == "ruckig" and seen["scheduler"] == "tcp://10.0.0.1:8786"
    assert (seen["time_limit"], seen["max_shots"], seen["workers"]) == (2.5, 4, 3)
    assert seen["out"] == str(tmp_path / "m.jsonl") and seen["outcome"] is True


def test_parsers():
    assert parse_numbers("0.5, 1", "--speeds", "m/s") == (0.5, 1.0)
    assert parse_grid("20X3") == (20, 3)
    assert parse_grid("4x3x2", 3) == (4, 3, 2)
    assert parse_numbers("-45,0", "--headings", "deg") == (-45.0, 0.0)


def test_help_explains_units(capsys):
    with pytest.raises(SystemExit) as info:
        main(["map", "--help"])
    assert info.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    for word in ("[m/s]", "[deg]", "[m]", "[s]", "--plot", "NXxNY"):
        assert word in text


def test_the_installed_command_sweeps_and_draws(tmp_path):
    command = shutil.which("optraj", path=str(Path(sys.executable).parent))
    assert command is not None, "the optraj entry point is not installed next to python"
    table = tmp_path / "map.parquet"
    done = subprocess.run(
        [command, *SWEEP, "--out", str(table)], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "planned" in done.stdout and len(sweeps.read_parquet(table)) == 8
    bad = subprocess.run(
        [command, "map", "sawyer", "--grid", "0x2"], capture_output=True, text=True, check=False
    )
    assert bad.returncode == 2 and "grid must be an integer >= 1, got 0" in bad.stderr
