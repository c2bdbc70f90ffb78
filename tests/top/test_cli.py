"""Tests of the optraj command."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_support import error_line, refused
from conftest import get_robot
from viz_support import object_paths

import optraj.cli
import optraj.demo
from optraj import planners, problems
from optraj.cli import main

HAVE_MATPLOTLIB = True
try:
    import matplotlib  # noqa: F401
except ImportError:  # pragma: no cover - depends on the environment
    HAVE_MATPLOTLIB = False
HAVE_MESHCAT = True
try:
    import meshcat  # noqa: F401
except ImportError:  # pragma: no cover - depends on the environment
    HAVE_MESHCAT = False


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """One run of ``optraj demo`` (it takes a few seconds), in a scratch directory."""
    cwd = tmp_path_factory.mktemp("demo")
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(cwd)
        out = io.StringIO()
        status = main(["demo", "--out", "plots"], out=out)
    return status, out.getvalue(), cwd / "plots"


def _row(text: str, label: str) -> str:
    return next(line for line in text.splitlines() if line.startswith(f"  {label} "))


# ------------------------------------------------------------------------------ demo


@pytest.mark.slow
def test_demo_is_short_and_leads_with_the_pool_shot(demo):
    status, text, _ = demo
    assert status == 0
    lines = text.splitlines()
    assert len(lines) <= 40
    assert lines[0].startswith("optraj demo: a Sawyer arm strikes a pool ball")
    assert "right_j0 " not in text  # the limit tables are optraj robots NAME's
    # Names say what things are.
    assert "seed" not in text.replace("plan-pull-back.json", "")


def test_robots_lists_names():
    out = io.StringIO()
    assert main(["robots"], out=out) == 0
    assert out.getvalue().splitlines()[0].startswith("paddle4")


def test_missing_optional_robot_fails_with_one_line(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "example_robot_data", None)
    assert main(["robots", "panda"], out=io.StringIO()) == 2
    line = error_line(capsys)
    assert line.startswith("optraj: error: robots.load('panda') needs the package")


def test_version_is_the_installed_one(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.strip() == f"optraj {version('optraj')}"
    assert optraj.__version__ == version("optraj")  # one source: pyproject.toml
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = optraj.nope


def test_unknown_command_exits_with_usage_error():
    with pytest.raises(SystemExit) as info:
        main(["fly"])
    assert info.value.code == 2


def test_console_script_module_runs():
    done = subprocess.run(
        [sys.executable, "-m", "optraj.cli", "robots"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "sawyer" in done.stdout


def test_demo_gives_the_other_tasks_verdicts(demo):
    _, text, _ = demo
    section = text.split("other tasks, judged by the same checker")[1]
    assert "two blocks over their table, quintic phases: 16.526 s, ok" in section
    assert "lspb phases" in section
    # The ECE486 paddle task ends at the closed-form contact configuration.
    assert "ends at q = (0.9000, 0.3911, 0.9985, -0.3911), ok" in section


def test_demo_says_what_each_planner_did_and_why(demo):
    _, text, _ = demo
    section = text.split("what each planner did")[1].split("\ntracking:")[0]
    best = _row(section, "optimal control (min time)")
    assert " ok " in best and "within every limit" in best
    assert "velocity 100%" in best and "cue 0.000 mm off the line" in best
    assert " ok " in _row(section, "optimal control (min jerk)")
    pull = _row(section, "pull-back + constant-speed strike")
    assert " FAIL " in pull and "acceleration unbounded (jump)" in pull
    assert "starts the strike line at full speed from rest" in pull
    # The five classic and time-optimal strikes share one reason: one line.
    refused = _row(section, "cubic, quintic, lspb, toppra, ruckig strikes:")
    assert "refused, the strike line at 1 m/s needs joint 'right_j1'" in refused
    assert "at the problem's contact configuration" in refused
    why = _row(section, "why optimal control (min time) succeeds:")
    assert "chooses where the cue meets the ball" in why
    assert len(optraj.cli.PLANNERS["pool-shot"]) == 8  # 3 planned lines + 5 in one refusal


def test_demo_tracks_the_plan_with_both_controllers(demo):
    _, text, _ = demo
    section = text.split("tracking: the minimum-time optimal-control plan")[1]
    assert "within 80% of the limits" in section
    for label in ("pseudo-inverse PID", "differential-IK QP"):
        cells = _row(section, label).removeprefix(f"  {label}").split()
        # tool [mm], off the line [mm], speed error [%], worst command [% of a limit], step [us]
        tool, line, speed = float(cells[0]), float(cells[2]), float(cells[4])
        worst, step = float(cells[6].rstrip("%")) / 100, float(cells[8])
        assert 0.0 < line <= tool < 20.0  # [mm]
        assert 0.0 <= speed < 10.0  # [%]
        assert step > 0.0 and worst > 0.0
        if label == "differential-IK QP":  # never beyond a limit; the pseudo-inverse may be
            assert worst <= 1.0


def test_demo_says_where_the_ball_went_for_each_tracked_plan(demo):
    _, text, _ = demo
    section = text.split("where the ball went (MuJoCo")[1]
    for label in ("plan alone", "pseudo-inverse PID", "differential-IK QP"):
        row = _row(section, label)
        assert row.endswith("on target"), row
        cells = row.removeprefix(f"  {label}").split()
        heading, speed, launch = float(cells[0]), float(cells[2]), float(cells[4])
        assert abs(heading) <= 0.5 and abs(speed) <= 2.0  # [deg], [%]
        # [m/s] (1 + e) x 1 m/s from the plan alone's rigid cue, less from the arm's (about
        # 2 kg effective mass)
        assert 1.5 < launch < 1.85


def test_demo_writes_plots_and_plans_that_check(demo, capsys):
    _, text, out_dir = demo
    plans = [
        "plan-pull-back.json",
        "plan-optimal-control.json",
        "plan-optimal-control-tracked.json",
    ]
    pictures = ["profiles.png", "tool_speed.png", "tracking.png"] if HAVE_MATPLOTLIB else []
    for name in [*pictures, *plans]:
        assert (out_dir / name).stat().st_size > 1000, name
        assert name in text.split("open next")[1]
    assert "README.md" in text and "notebooks/02_pool_strike.ipynb" in text
    page = out_dir / "pool-shot.html"
    assert page.exists() == HAVE_MESHCAT == ("pool-shot.html" in text)
    if HAVE_MESHCAT:
        drawn = object_paths(page.read_text())
        scene = {"/meshcat/optraj/scene/ball", "/meshcat/optraj/scene/table/cloth"}
        assert scene <= drawn and "/meshcat/optraj/robot/visuals/tool/cue" in drawn
        blocks = object_paths((out_dir / "pick-and-place.html").read_text())
        assert any("block_0" in path for path in blocks), sorted(blocks)
    for name, status in (("plan-optimal-control-tracked.json", 0), ("plan-pull-back.json", 1)):
        out = io.StringIO()
        assert main(["check", str(out_dir / name)], out=out) == status
        assert "problem pool-shot" in out.getvalue()


def test_demo_creates_nothing_in_the_working_directory_but_out(demo):
    _, _, out_dir = demo
    assert sorted(p.name for p in out_dir.parent.iterdir()) == [out_dir.name]


# ------------------------------------------------------------------------ plan and check


def _plan_then_check(tmp_path, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    assert main(["plan", *argv], out=out) == 0
    summary = out.getvalue()
    traj = planners.Trajectory.from_json(tmp_path / "traj.json")
    out = io.StringIO()
    status = main(["check", "traj.json"], out=out)
    return summary, traj, status, out.getvalue()


def test_plan_then_check_a_pool_shot_with_ruckig(tmp_path, monkeypatch):
    # Ruckig's entry into the line at 1 m/s is beyond right_j1's speed limit: plan at 0.5 m/s.
    summary, traj, status, report = _plan_then_check(
        tmp_path,
        monkeypatch,
        ["sawyer", "--problem", "pool-shot", "--planner", "ruckig", "--speed", "0.5"],
    )
    assert traj.metadata["robot"] == "sawyer" and traj.metadata["problem"] == "pool-shot"
    assert traj.metadata["problem_options"] == {"speed": 0.5}
    assert [phase.name for phase in traj.phases] == ["approach", "strike", "stop"]
    expected = planners.check(traj, problems.sawyer_pool_shot(speed=0.5))
    assert status == (0 if expected.ok else 1)
    assert report.splitlines()[0] == (
        "traj.json: checked against robot sawyer, problem pool-shot (speed 0.5 m/s)"
    )
    assert report.rstrip().endswith(str(expected).splitlines()[-1])
    assert "ruckig strike" in summary and "Wrote traj.json" in summary.replace("\n", " ")


def test_plan_then_check_point_to_point_with_quintic(tmp_path, monkeypatch):
    goal = [0.3, -0.9, 0.2, 1.8, -0.1, 0.8, 3.0]
    summary, traj, status, report = _plan_then_check(
        tmp_path,
        monkeypatch,
        ["sawyer", "--problem", "point-to-point", "--planner", "quintic", "--q-goal"]
        + [str(v) for v in goal],
    )
    robot = get_robot("sawyer")
    expected = planners.check(traj, problems.PointToPoint(robot, robot.home, goal))
    assert status == (0 if expected.ok else 1)
    np.testing.assert_allclose(traj.sample(traj.duration).q, goal, atol=1e-9)
    options = traj.metadata["problem_options"]
    np.testing.assert_allclose(options["q_start"], robot.home, atol=0.0)
    assert ("PASS" if expected.ok else "FAIL") in report
    assert "quintic" in summary


def test_plan_point_to_point_takes_a_pose_name_and_a_duration(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    robot = get_robot("youbot")
    argv = ["plan", "youbot", "--problem", "point-to-point", "--planner", "cubic"]
    assert main([*argv, "--q-goal", "candle", "--duration", "3", "--out", "m.json"]) == 0
    traj = planners.Trajectory.from_json(tmp_path / "m.json")
    assert traj.duration == pytest.approx(3.0)
    np.testing.assert_allclose(traj.sample(3.0).q, robot.poses["candle"], atol=1e-12)


def test_plan_paddle_strike_and_pick_and_place_check_out(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for argv in (
        ["paddle4", "--problem", "paddle-strike", "--planner", "quintic", "--ball", "1.1", "-0.8",
         "0.7"],
        ["youbot", "--problem", "pick-and-place", "--planner", "quintic"],
    ):  # fmt: skip
        assert main(["plan", *argv], out=io.StringIO()) == 0
        assert main(["check", "traj.json", "--rate", "200"], out=io.StringIO()) == 0
    traj = planners.Trajectory.from_json(tmp_path / "traj.json")
    assert traj.metadata["planner"] == "pick and place (quintic)"


def test_check_a_file_without_a_problem_uses_the_robot_limits(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    robot = get_robot("sawyer")
    traj = planners.Ruckig().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.2))
    Path("bare.json").write_text(traj.to_json())
    assert main(["check", "bare.json"], out=io.StringIO()) == 2
    assert "give --robot" in error_line(capsys)
    out = io.StringIO()
    assert main(["check", "bare.json", "--robot", "sawyer"], out=out) == 0
    assert "its joint limits only" in out.getvalue()
    assert "PASS" in out.getvalue()


def test_help_of_every_command_explains_units(capsys):
    wanted = {
        "plan": ["[m/s]", "[m]", "[deg]", "[rad or m]", "[s]"],
        "check": ["[Hz]", "[rad or m]", "[N m]"],
        "demo": ["[s]", "mm"],
        "bench": ["--quick"],
    }
    for command, words in wanted.items():
        with pytest.raises(SystemExit) as info:
            main([command, "--help"])
        assert info.value.code == 0
        text = " ".join(capsys.readouterr().out.split())
        for word in words:
            assert word in text, (command, word)


# --------------------------------------------------------------------------- error paths

PLAN = ["plan", "sawyer", "--problem", "pool-shot", "--planner"]


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["plan", "sawer", "--problem", "pool-shot", "--planner", "ruckig"],
         "unknown robot 'sawer'; known: paddle4, sawyer"),
        ([*PLAN, "fastest"],
         "unknown planner for pool-shot 'fastest'; known: pull-back, cubic, quintic, lspb, toppra, "
         "ruckig, optimal-control, optimal-control-jerk"),
        (["plan", "sawyer", "--problem", "pool", "--planner", "ruckig"],
         "unknown problem 'pool'; known: pool-shot, paddle-strike, pick-and-place, "
         "point-to-point (did you mean 'pool-shot'?)"),
        (["plan", "youbot", "--problem", "pool-shot", "--planner", "ruckig"],
         "problem 'pool-shot' is for robot 'sawyer', not 'youbot'; problems for youbot: "
         "pick-and-place, point-to-point"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "pull-back"],
         "unknown planner for point-to-point 'pull-back'; known: cubic,"),
        ([*PLAN, "ruckig", "--q-goal", "0"],
         "--q-goal does not apply to problem 'pool-shot'"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal", "1"],
         "--q-goal needs 7 values [rad or m]"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic"],
         "the goal equals the start"),
        ([*PLAN, "optimal-control", "--speed", "2.5"],
         "strike speed 2.5 m/s needs right_j0"),
        ([*PLAN, "ruckig", "--speed", "0.5", "--out", "no/such/dir/traj.json"],
         "cannot write 'no/such/dir/traj.json'"),
        (["plan", "sawyer", "--problem", "pool-shot"],
         "optraj plan: error: the following arguments are required: --planner"),
        (["check", "missing.json"], "no trajectory file at 'missing.json'"),
        ([*PLAN, "ruckig", "--limit-scale", "1e-300"],
         "--limit-scale must be in [1e-06, 1], got 1e-300"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal", "0",
          "0", "0", "0", "0", "0", "0", "--duration", "1e200"],
         "--duration must be <= 86400 s, got 1e+200 s"),  # not an OverflowError
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal",
          "nan", "0", "0", "0", "0", "0", "0"], "--q-goal must be finite"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal",
          "home", "0"], "--q-goal takes joint positions [rad or m], one per joint, or one pose"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal",
          "candle"], "--q-goal takes 7 joint positions [rad or m] or a pose name (home"),
        (["check", "missing.json", "--rate", "1e9"], "--rate must be <= 1e+06 Hz, got 1e+09 Hz"),
    ],
)  # fmt: skip
def test_errors_exit_2_with_one_line(argv, expected, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    line = refused(argv, capsys)
    assert line.startswith("optraj")
    assert expected in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('{"format": "optraj.trajectory/1", "breakpoints": [0, 1', "trajectory JSON is malformed"),
        ("[1, 2]", "'bad.json': not an optraj trajectory"),
        (
            '{"format": "optraj.trajectory/1"}',
            "'bad.json': trajectory data is missing or has a malformed",
        ),
        ("\udcff\udcfe not text", "cannot read 'bad.json'"),
    ],
)
def test_check_of_a_bad_file_exits_2_with_one_line(text, expected, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    Path("bad.json").write_bytes(text.encode("utf-8", "surrogateescape"))
    assert main(["check", "bad.json"], out=io.StringIO()) == 2
    assert expected in error_line(capsys)


def _point_to_point_file(path: Path) -> planners.Trajectory:
    """A small Sawyer move written to ``path`` as ``optraj plan`` writes it."""
    robot = get_robot("sawyer")
    goal = robot.home + 0.2
    traj = planners.Quintic().plan(problems.PointToPoint(robot, robot.home, goal))
    options = {"q_start": robot.home.tolist(), "q_goal": goal.tolist()}
    optraj.cli.tag_trajectory(traj, "sawyer", "point-to-point", options)
    traj.to_json(path)
    return traj


@pytest.mark.parametrize(
    ("edit", "expected"),
    [
        # what json cannot read: nesting (a RecursionError) and long integers (a ValueError)
        (lambda d: {**d, "metadata": {"x": "@"}}, "trajectory JSON is malformed in 'bad.json': "
         "nested too deeply"),
        # a 1e300 s trajectory (numpy's "Maximum allowed size exceeded" when sampled)
        (lambda d: {**d, "breakpoints": [0.0, 1e300]}, "must be <= 86400 s, got 1e+300 s"),
        # numbers in the recorded problem that are bools or strings
        (lambda d: _with_options(d, duration=True), "--duration must be a numeric"),
        (lambda d: _with_options(d, q_goal=[str(v) for v in d["metadata"]["problem_options"]
                                            ["q_goal"]]), "--q-goal must be a numeric"),
        (lambda d: _with_options(d, q_goal=[True] * 7), "--q-goal must be a numeric"),
        (lambda d: _with_options(d, limit_scale="0.5"), "--limit-scale must be a numeric"),
    ],
)  # fmt: skip
def test_check_of_a_malformed_or_oversized_file_exits_2_with_one_line(
    edit, expected, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    _point_to_point_file(Path("good.json"))
    data = edit(json.loads(Path("good.json").read_text()))
    text = json.dumps(data).replace('"@"', "[" * 100_000 + "]" * 100_000)
    Path("bad.json").write_text(text)
    assert main(["check", "bad.json"], out=io.StringIO()) == 2
    assert expected in error_line(capsys)


def _with_options(data: dict, **options) -> dict:
    data["metadata"]["problem_options"].update(options)
    return data


def test_check_refuses_a_bad_rate_and_an_oversized_file(tmp_path, monkeypatch, capsys):
    from optraj import planners

    monkeypatch.chdir(tmp_path)
    _point_to_point_file(Path("t.json"))
    assert main(["check", "t.json"], out=io.StringIO()) == 0
    assert main(["check", "t.json", "--rate", "1e300"], out=io.StringIO()) == 2  # not a traceback
    assert error_line(capsys) == "optraj: error: --rate must be <= 1e+06 Hz, got 1e+300 Hz"
    monkeypatch.setattr(planners.trajectory, "MAX_JSON_BYTES", 1000)
    assert main(["check", "t.json"], out=io.StringIO()) == 2
    assert "bytes, more than the 1000 bytes of any trajectory file" in error_line(capsys)


def test_an_os_error_in_a_command_exits_2_with_one_line(capsys):
    class Denied(io.StringIO):
        def write(self, text):
            raise PermissionError(13, "Permission denied", "/some/file")

    assert main(["robots"], out=Denied()) == 2
    assert error_line(capsys) == "optraj: error: cannot use '/some/file': Permission denied"


def test_check_of_bad_problem_metadata_exits_2(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    robot = get_robot("sawyer")
    traj = planners.Ruckig().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.2))
    traj.metadata.update(robot="sawyer", problem="pool-shot", problem_options={"ball": "far"})
    traj.to_json("odd.json")
    assert main(["check", "odd.json"], out=io.StringIO()) == 2
    assert error_line(capsys).startswith("optraj: error: ")


# --------------------------------------------------------------------------------- bench


def _installed_at(monkeypatch, root: Path) -> None:
    """Make optraj look installed at ``root``: the bench runner is looked for beside it."""
    monkeypatch.setattr(optraj, "__file__", str(root / "optraj" / "__init__.py"))


def test_bench_without_the_source_checkout_exits_2(monkeypatch, capsys, tmp_path):
    _installed_at(monkeypatch, tmp_path)
    assert main(["bench", "--quick"], out=io.StringIO()) == 2
    assert "benchmarks ship with the source checkout" in error_line(capsys)


def test_bench_runs_the_runner_with_this_python_and_forwards_quick(monkeypatch, tmp_path):
    runner = tmp_path / "benchmarks" / "run_all.py"
    runner.parent.mkdir()
    runner.write_text(
        "import json, os, sys\n"
        "json.dump({'argv': sys.argv[1:], 'cwd': os.getcwd(), 'python': sys.executable},"
        " open('seen.json', 'w'))\n"
        "sys.exit(3)\n"
    )
    _installed_at(monkeypatch, tmp_path)
    monkeypatch.chdir(tmp_path / "benchmarks")
    assert main(["bench", "--quick", "--out", "mine"], out=io.StringIO()) == 3
    seen = json.loads((tmp_path / "seen.json").read_text())
    # --out is taken from the caller's directory, and made.
    folder = tmp_path / "benchmarks" / "mine"
    assert seen["argv"] == ["--quick", "--out", str(folder.resolve())] and folder.is_dir()
    assert Path(seen["cwd"]).resolve() == tmp_path.resolve()
    assert Path(seen["python"]).resolve() == Path(sys.executable).resolve()


def test_bench_finds_the_runner_next_to_the_packages(monkeypatch):
    root = Path(optraj.__file__).resolve().parents[1]
    ran = []

    def run(command, **options):
        ran.append((command, options["cwd"]))
        return subprocess.CompletedProcess(command, 0)

    monkeypatch.setattr(subprocess, "run", run)
    assert main(["bench"], out=io.StringIO()) == 0
    [(command, cwd)] = ran
    assert command[:3] == [sys.executable, str(root / "benchmarks" / "run_all.py"), "--out"]
    assert cwd == root
    # By default a new, empty folder outside the checkout: the committed results stay as
    # they are (make bench passes --out benchmarks/results).
    folder = Path(command[3])
    assert folder.is_dir() and not any(folder.iterdir())
    assert not folder.resolve().is_relative_to(root)
    folder.rmdir()


def test_bench_refuses_an_out_folder_it_cannot_make(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert main(["bench", "--out", str(tmp_path / "file" / "sub")], out=io.StringIO()) == 2
    assert error_line(capsys).startswith("optraj: error: argument --out: cannot create")


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([*PLAN, "ruckig", "--speed", "-1"], "argument --speed: speed must be > 0 m/s"),
        ([*PLAN, "ruckig", "--ball", "5", "5", "5"], "argument --ball: robot 'sawyer': no "),
        (["plan", "paddle4", "--problem", "paddle-strike", "--planner", "quintic", "--ball", "9",
          "9", "9"], "argument --ball: point (9, 9, 9) m is outside the workspace"),
        ([*PLAN, "ruckig"], "argument --speed: the strike line at 1 m/s needs joint 'right_j1'"),
        ([*PLAN, "nope"], "argument --planner: unknown planner for pool-shot 'nope'"),
        (["plan", "sawyer", "--problem", "nope", "--planner", "ruckig"],
         "argument --problem: unknown problem 'nope'"),
        (["plan", "sawyer", "--problem", "point-to-point", "--planner", "cubic", "--q-goal", "9",
          "9", "9", "9", "9", "9", "9"], "argument --q-goal: joint 'right_j1' position 9 rad"),
        (["check", "t.json", "--robot", "nope"], "argument --robot: unknown robot 'nope'"),
        (["demo", "--out", "t.json/x"], "argument --out: cannot create the output folder"),
        (["map", "sawyer", "--speeds", "-1"], "argument --speeds: speeds must be > 0 m/s"),
        (["map", "sawyer", "--grid", "0x0"], "argument --grid: grid must be an integer >= 1"),
        (["map", "sawyer", "--time-limit", "-1"], "argument --time-limit: time_limit must be"),
        (["map", "sawyer", "--workers", "-1"], "argument --workers: workers must be an integer"),
        (["map", "sawyer", "--max-shots", "-1"], "argument --max-shots: max_shots must be"),
        (["map", "sawyer", "--samples", "0"], "argument --samples: samples must be an integer"),
        (["map", "sawyer", "--seed", "-1", "--samples", "2"], "argument --seed: seed must be"),
        (["map", "sawyer", "--x", "5,6"], "argument --x: x must be <="),
        (["map", "paddle4", "--z", "5,6"], "argument --z: z must be <= 0.7 m"),
        (["map", "sawyer", "--scheduler", "nothing"], "argument --scheduler: scheduler must be"),
        (["map", "--plot", "none.parquet"], "argument --plot: no sweep rows in 'none.parquet'"),
        (["map", "sawyer", "--out", "t.json/m.parquet"], "argument --out: cannot use"),
        (["robots", "nope"], "unknown robot 'nope'"),  # the positional NAME
    ],
)  # fmt: skip
def test_every_error_names_its_option(argv, expected, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _point_to_point_file(Path("t.json"))
    assert main(argv, out=io.StringIO()) == 2
    assert expected in error_line(capsys)


@pytest.mark.parametrize(("robot", "pose"), [("sawyer", "neutral"), ("youbot", "candle")])
def test_a_goal_pose_that_renames_home_is_not_suggested(robot, pose, capsys):
    # Sawyer's neutral pose is its home (the intera SDK's neutral), as youBot's candle is.
    argv = ["plan", robot, "--problem", "point-to-point", "--planner", "cubic", "--q-goal", pose]
    assert main(argv, out=io.StringIO()) == 2
    line = error_line(capsys)
    assert "the goal equals the start" in line and pose not in line.split("got")[0]
    assert "or a --duration to hold still" in line
