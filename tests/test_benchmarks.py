"""The benchmark scripts run (in their quick form) and write their tables."""

from __future__ import annotations

import importlib.util
import io
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _load(name: str, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))  # the scripts import benchmarking
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_time_optimal_quick_run_writes_its_table(tmp_path, monkeypatch):
    module = _load("time_optimal", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    table = (tmp_path / "time_optimal.md").read_text()
    assert "| toppra |" in table and "| ruckig |" in table
    # Ruckig, time-optimal under the same velocity/acceleration/jerk limits as the bound, sits
    # on it; the others ignore jerk, so they may undercut it only slightly.
    rows = [line for line in table.splitlines() if line.startswith(("| sawyer", "| youbot"))]
    assert len(rows) == 2
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        ratios = [float(c) for c in cells[2:]]
        assert ratios[-1] == 1.0
        assert min(ratios) > 0.9


@pytest.mark.slow
def test_strike_quick_run_writes_its_table(tmp_path, monkeypatch):
    module = _load("strike", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    text = (tmp_path / "strike.md").read_text()
    table, extras = text.split("## OptimalControl solve times")
    extras, by_speed = extras.split("## OptimalControl against the strike speed")
    speed_rows = [
        [c.strip() for c in line.strip("|").split("|")]
        for line in by_speed.splitlines()
        if line.startswith("| ") and not line.startswith(("| speed", "|---"))
    ]
    assert [row[0] for row in speed_rows] == [f"{v:g}" for v in module.QUICK_SPEEDS]
    speed_header = next(line for line in by_speed.splitlines() if line.startswith("| speed"))
    assert speed_header.rstrip(" |").endswith("| max time to an error [ms]")
    for row in speed_rows:  # one ball at 0.1 and 1 m/s: planned, and passed by the checker
        assert row[2] == "1/1" and row[3] == row[4] == "0"
        assert len(row) == 11 and row[-1] == "-"  # no plan raised: no time to an error
    header = next(line for line in table.splitlines() if line.startswith("| planner |"))
    columns = [c.strip() for c in header.strip("|").split("|")]
    assert columns[:4] == ["planner", "success", "motion time [s]", "vs cubic"]
    assert "peak jerk" in columns and "speed error [%]" in columns and "errors" in columns
    rows = {
        cells[0]: dict(zip(columns, cells, strict=True))
        for line in table.splitlines()
        if line.startswith("| ") and not line.startswith(("| planner", "|---"))
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    expected = [label for label, _ in module.planners_to_compare()]
    assert list(rows) == expected
    assert expected[:6] == [
        "pull-back + line",
        "cubic strike",
        "quintic strike",
        "lspb strike",
        "toppra strike",
        "ruckig strike",
    ]
    for row in rows.values():
        assert row["success"].split()[0].endswith("/4")
    # The seed jumps to full speed at the entry: planned every time, never within the limits.
    solved = int(rows["optimal control (min time)"]["success"].split("/")[0])
    assert solved >= 3  # it chooses its own contact configuration
    assert all(f"| {run} |" in extras for run in ("cold", "first plan", "warm"))
    lines = extras.splitlines()
    runs = [
        c.strip() for c in next(x for x in lines if x.startswith("| run |")).strip("|").split("|")
    ]
    cold = next(x for x in lines if x.startswith("| cold |"))
    cells = dict(zip(runs, [c.strip() for c in cold.strip("|").split("|")], strict=True))
    # The wall time's parts: the contact search, and the NLP's evaluations within its time.
    assert 0.0 < float(cells["median contact choice [ms]"]) < float(cells["median wall [ms]"])
    assert 0.0 < float(cells["median NLP evaluations [ms]"]) < float(cells["median NLP [ms]"])
    seed = rows["pull-back + line"]
    assert seed["success"].startswith("0/4") and "acceleration 4" in seed["checker failures"]
    assert seed["errors"] == "-"
    # Ruckig and the quintic keep every limit or raise: none of their trajectories fails.
    assert rows["ruckig strike"]["checker failures"] == "-"
    assert rows["quintic strike"]["checker failures"] == "-"


def test_the_speed_table_counts_the_contact_choice_and_window_refusals_as_refused(monkeypatch):
    from optraj.errors import CONTACT_CHOICE, WINDOW_CHECK, InfeasibleError, SolverError

    module = _load("strike", monkeypatch)
    contact = InfeasibleError(
        "no contact reaches 2.5 m/s", limit="velocity", joint="right_j1", found_by=CONTACT_CHOICE
    )
    window = InfeasibleError(
        "window past the limits", limit="acceleration", joint="right_j3", found_by=WINDOW_CHECK
    )
    torque = InfeasibleError("torque limits stay exceeded", limit="effort", joint="right_j1")
    assert module._refused(contact) and module._refused(window)
    reach = InfeasibleError("the ball is out of reach", limit="position")
    # Neither the limit nor a chained solver error makes a refusal: only the finding's mark.
    duration = InfeasibleError("contact_time is too short", limit="velocity", joint="J1")
    duration.__cause__ = SolverError("ipopt", "Infeasible_Problem_Detected")
    for other in (torque, reach, duration, SolverError("ipopt", "Maximum_Iterations_Exceeded")):
        assert not module._refused(other)


@pytest.mark.slow
def test_tracking_quick_run_writes_its_tables(tmp_path, monkeypatch):
    module = _load("tracking", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    text = (tmp_path / "tracking.md").read_text()
    table, timing = text.split("## Controller time per step")
    rows = {
        (cells[0], cells[1]): cells
        for line in table.splitlines()
        if line.startswith("| ") and not line.startswith(("| condition", "|---"))
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    labels = ["pseudo-inverse PID", "differential-IK QP", "joint PD"]
    assert list(rows) == [(c, label) for c in module.CONDITIONS for label in labels]
    # On the plan at the limits the pseudo-inverse asks for more than a limit, the QP never.
    over = {label: rows[("at the limits", label)] for label in labels}
    assert over["pseudo-inverse PID"][6] != "0/2" and float(over["pseudo-inverse PID"][7]) > 1.0
    assert over["differential-IK QP"][6] == "0/2"
    assert float(over["differential-IK QP"][7]) <= 1.0
    assert "| differential-IK QP |" in timing and "| 1.00 |" in timing


@pytest.mark.slow
def test_run_all_runs_each_benchmark_draws_the_plots_and_rewrites_the_readme(tmp_path, monkeypatch):
    module = _load("run_all", monkeypatch)
    module_names = ["time_optimal", "strike", "tracking", "outcome", "sweep", "peers", "clearance"]
    calls = []

    def fake(name):
        def main(argv):
            calls.append((name, argv))
            out = Path(argv[argv.index("--out") + 1])
            out.write_text(
                f"# {name}\n\nCommand: `python benchmarks/{name}.py --quick`\n\n"
                f"| a | b |\n|---|---|\n| {name} | 1 |\n\n## Durations\n\n"
                f"| c |\n|---|\n| {name} durations |\n\n## Controller time per step\n\n"
                f"| d |\n|---|\n| {name} timing |\n\n## Targets\n\n"
                f"| e |\n|---|\n| {name} targets |\n\n## Throughput\n\n"
                f"| f |\n|---|\n| {name} throughput |\n\n## A million shots\n\n"
                f"| g |\n|---|\n| {name} million |\n\n## Pick-and-place\n\n"
                f"| h |\n|---|\n| {name} pick |\n"
            )
            return 0

        return main

    monkeypatch.setattr(module, "BENCHMARKS", [(n, fake(n), []) for n in module_names])
    readme = tmp_path / "README.md"
    readme.write_text(f"# optraj\n\nbefore\n\n{module.BEGIN}\nstale\n{module.END}\n\nafter\n")
    monkeypatch.setattr(module, "README", readme)
    out = tmp_path / "results"
    assert module.main(["--quick", "--out", str(out), "--readme"]) == 0
    assert [name for name, _ in calls] == module_names
    assert all("--quick" in argv for _, argv in calls)
    for name in ("profiles.png", "strike_speed.png", "tracking.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = readme.read_text()
    assert "stale" not in text and text.startswith("# optraj\n\nbefore") and "after" in text
    assert "| strike | 1 |" in text and "| tracking timing |" in text
    assert "| time_optimal durations |" in text and "| outcome targets |" in text
    assert "| sweep throughput |" in text and "| sweep million |" in text
    assert "| peers | 1 |" in text and "`python benchmarks/peers.py --quick`" in text
    assert "/outcome_paths.png)" in text and "/outcome_heading.png)" in text
    assert f"]({out.resolve()}/tracking.png)" in text  # outside the repository: absolute


def _git_status() -> str:
    done = subprocess.run(
        ["git", "status", "--porcelain", "--untracked-files=all"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout


@pytest.mark.slow
@pytest.mark.skipif(
    shutil.which("git") is None or not (ROOT / ".git").exists(), reason="not a git checkout"
)
def test_run_all_without_out_leaves_the_checkout_clean(tmp_path, monkeypatch):
    # `optraj bench --quick` runs run_all.py with a new folder: the committed results and the
    # README stay as they are. The whole quick run takes minutes, so the cheapest benchmark
    # (time_optimal) stands in for all of them, and the plots (solves; drawn in the test above)
    # are left out.
    module = _load("run_all", monkeypatch)
    cheapest = _load("time_optimal", monkeypatch)
    monkeypatch.setattr(module, "BENCHMARKS", [("time_optimal", cheapest.main, [])])
    monkeypatch.setattr(module, "draw_plots", lambda out: [])
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    before = _git_status()
    assert module.main(["--quick"]) == 0
    assert _git_status() == before
    [folder] = tmp_path.iterdir()
    assert folder.name.startswith("optraj-bench-")
    assert "| ruckig |" in (folder / "time_optimal.md").read_text()


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_is_drawn_on_a_terminal_only_with_the_whole_label(monkeypatch):
    module = _load("benchmarking", monkeypatch)
    piped = io.StringIO()
    monkeypatch.setattr(sys, "stderr", piped)
    for done in range(4):
        module.progress(done, 3, "planning")
    assert piped.getvalue() == ""  # not even a carriage return
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    label = "shot 12: optimal control (min time) with noise"  # longer than 28 characters
    module.progress(0, 2, label)
    time.sleep(0.15)  # tqdm redraws at most every 0.1 s
    module.progress(1, 2, label)
    module.progress(2, 2, label)
    text = terminal.getvalue()
    assert label in text and "1/2" in text and "2/2" in text and text.endswith("\n")
    assert "<" in text  # elapsed<left


def test_run_all_refuses_a_readme_without_markers(tmp_path, monkeypatch):
    module = _load("run_all", monkeypatch)
    readme = tmp_path / "README.md"
    readme.write_text("# optraj\n")
    with pytest.raises(ValueError, match="no results markers"):
        module.rewrite_readme(readme, "section")


@pytest.fixture(scope="module")
def outcome_quick(tmp_path_factory):
    """One quick outcome run in this process: (module, its folder, its table)."""
    folder = tmp_path_factory.mktemp("outcome")
    with pytest.MonkeyPatch.context() as monkeypatch:
        module = _load("outcome", monkeypatch)
        assert module.main(["--quick", "--out", str(folder / "outcome.md")]) == 0
    return module, folder, (folder / "outcome.md").read_text()


@pytest.mark.slow
def test_outcome_quick_run_judges_every_strike_by_the_ball(outcome_quick):
    _, tmp_path, text = outcome_quick
    rows = {
        tuple(cells[:4]): cells
        for line in text.split("## Paddle")[0].splitlines()
        if line.startswith("| 1 |")
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    assert rows[("1", "min-time OCP", "plan alone", "-")][5].startswith("1/1")
    assert rows[("1", "min-time OCP", "DiffIKQP", "nominal")][5].startswith("1/1")
    assert "| DiffIKQP | 1/1 | 1/1" in text.split("## Paddle")[1]
    targets = {
        cells[0]: cells
        for line in text.split("## Targets")[1].split("## Every")[0].splitlines()
        if line.startswith("| ") and not line.startswith(("| target", "|---"))
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    assert targets["min-time OCP alone within"][1:] == ["100 %", "100.0 %", "yes"]
    assert targets["DiffIKQP within, 1 m/s, nominal"][-1] == "yes"
    assert targets["paddle DiffIKQP within 0.5 deg of the normal"][-1] == "yes"
    for name in ("outcome_paths.png", "outcome_heading.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "Errors (defects; the case's other rows stand): none" in text


@pytest.mark.slow
def test_outcome_is_the_same_from_worker_processes(outcome_quick, tmp_path, monkeypatch):
    _, _, serial = outcome_quick
    module = _load("outcome", monkeypatch)
    monkeypatch.setitem(sys.modules, "outcome", module)  # spawned workers import it by name
    out = tmp_path / "outcome.md"
    assert module.main(["--quick", "--workers", "2", "--out", str(out)]) == 0
    assert out.read_text() == serial


def test_fingerprint_compare_finds_a_moved_number_and_passes_an_unmoved_one(tmp_path, monkeypatch):
    module = _load("fingerprint", monkeypatch)
    before = {"shot": {"duration": 1.0, "q": [0.5, 0.25], "status": "ok"}}
    assert list(module.differences(before, before, 1e-9)) == []
    moved = {"shot": {"duration": 1.0 + 1e-6, "q": [0.5, 0.25], "status": "ok"}}
    assert list(module.differences(before, moved, 1e-9)) == ["/shot/duration: 1.0 -> 1.000001"]
    assert list(module.differences(before, moved, 1e-5)) == []
    renamed = {"shot": {"duration": 1.0, "q": [0.5, 0.25], "status": "failed"}}
    assert list(module.differences(before, renamed, 1e-9)) == ["/shot/status: 'ok' -> 'failed'"]
    assert module._is_wall("nlp_time") and module._is_wall("contact_time")
    assert not module._is_wall("motion_time") and not module._is_wall("duration_from")


@pytest.mark.slow
def test_sweep_quick_run_writes_its_tables(tmp_path, monkeypatch):
    module = _load("sweep", monkeypatch)
    out = tmp_path / "sweep.md"
    assert module.main(["--quick", "--out", str(out)]) == 0  # raises if a table differs
    text = out.read_text()
    throughput = text.split("## Throughput")[1].split("## Dask against")[0]
    rows = [
        [c.strip() for c in line.strip("|").split("|")]
        for line in throughput.splitlines()
        if line.startswith("| ") and not line.startswith("| planner")
    ]
    assert {(row[0], row[1]) for row in rows} == {("ruckig", "8")}
    executors = [(row[2], row[3]) for row in rows]
    assert executors[0] == ("serial (this process)", "0")
    assert {("local processes", "2"), ("Dask", "2")} <= set(executors)
    assert all(float(row[5]) > 0.0 for row in rows)  # shots/s
    assert all(float(row[7]) > 0.0 and float(row[8]) >= 0.0 for row in rows[1:])
    ones = [float(row[6]) for row in rows if row[3] == "1"]  # the faster of the two is 1
    assert max(ones) == 1.0 and 0.0 < min(ones) <= 1.0
    million = text.split("## A million shots")[1]
    hours = [float(line.split("|")[3]) for line in million.splitlines() if line.startswith("| 1")]
    assert len(hours) == 3 and hours[0] > hours[1] > hours[2]  # 1, 10, 100 machines
    assert (tmp_path / "sweep_map.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "## Map" in text and "4 shots at 0.5 m/s" in text


PEER_ROWS = [
    "quintic 2 s, rest",
    "quintic 2 s, boundary",
    "cubic 2 s, rest",
    "cubic 2 s, boundary",
    "quintic shortest, rest",
    "quintic shortest, boundary",
    "cubic shortest, rest",
    "cubic shortest, boundary",
    "LSPB, rest",
    "ViaPoints lspb",
    "ViaPoints quintic",
    "PointToPoint construction",
    "Ruckig, rest",
    "Ruckig, boundary",
    "Toppra, 100 intervals",
    "OptimalControl min time, NLP reused, vs bare CasADi",
    "OptimalControl min time, NLP reused, vs Drake",
    "OptimalControl first plan vs reused",
    "OptimalControl new planner object vs reused",
    "strike OCP warm re-plan vs cold",
    "strike OCP cold vs Ruckig strike",
    "DiffIKQP step vs pink + daqp",
]


def _table_rows(text: str, header: str) -> list[list[str]]:
    lines = text.split(header)[1].split("\n\n")[0].splitlines()[2:]  # past the header
    return [[c.strip() for c in line.strip("|").split("|")] for line in lines]


@pytest.mark.slow
def test_peers_quick_run_times_every_row_of_the_protocol(tmp_path, monkeypatch):
    module = _load("peers", monkeypatch)
    out = tmp_path / "peers" / "peers.md"
    assert module.main(["--quick", "--out", str(out)]) == 0  # with or without the peers
    text = out.read_text()
    assert "OMP_NUM_THREADS=1, OPENBLAS_NUM_THREADS=1, MKL_NUM_THREADS=1" in text
    assert "Command: `python benchmarks/peers.py --quick`" in text  # what run_all cites
    rows = _table_rows(text, "| row | optraj [us] | peer or reference [us] |")
    assert [row[0] for row in rows] == PEER_ROWS
    for label, ours, other, ratio, target, met, moves in rows:
        assert float(ours) > 0.0, label  # optraj is timed whatever the peers
        assert int(moves.split("/")[0]) >= 1, label
        if label == "PointToPoint construction":
            assert (other, ratio, target) == ("-", "-", "optraj <= 10 us")
        elif other.startswith("peer not installed ("):
            assert (ratio, met) == ("-", "-"), label
        else:
            assert float(other) > 0.0 and float(ratio) > 0.0, label
            assert met in ("met", "missed"), label
    by_label = {row[0]: row for row in rows}
    assert by_label["DiffIKQP step vs pink + daqp"][6] == "100/100"
    solvers = _table_rows(text, "| solver | moves solved |")
    assert [row[0] for row in solvers] == [
        "optraj OptimalControl('time')",
        "bare CasADi + IPOPT",
        "Drake KinematicTrajectoryOptimization + IPOPT",
    ]
    ours = solvers[0]
    assert ours[1] == "2" and float(ours[2]) >= 1.0 and 0.999 <= float(ours[3]) < 1.1


def test_peer_rows_leave_out_refused_and_failed_moves_and_divide_as_their_target_says(
    monkeypatch,
):
    from optraj.errors import InvalidInputError

    timing = _load("peer_timing", monkeypatch)

    def ours(k):
        if k == 1:
            raise InvalidInputError("refused", name="k")
        return lambda: k

    def other(k, result):
        assert result == k  # what optraj's untimed call returned
        if k == 2:
            raise RuntimeError("the peer fails")
        return lambda: -k

    seen = []
    spec = timing.Spec("row", ours, other, None, observe=lambda *a: seen.append(a))
    row = timing.measure(spec, 4, repeats=3)
    assert seen == [(0, 0, 0), (3, 3, -3)]
    assert len(row.ours) == len(row.other) == 2 and min(row.ours + row.other) > 0.0
    cells = row.cells()
    assert (
        cells[-1]
        == "2/4; optraj refused 1 (InvalidInputError); other side failed on 1 (RuntimeError)"
    )

    row.ours, row.other = [1e-6, 3e-6], [4e-6, 4e-6]  # medians 2 us and 4 us
    assert row.ratio() == pytest.approx(2.0) and row.met() == "met"  # peer / optraj >= 1
    quotient = timing.Row(timing.Spec("q", ours, other, None, kind="warm / cold", goal=0.2), 2)
    quotient.ours, quotient.other = [1e-6, 3e-6], [4e-6, 4e-6]
    assert quotient.ratio() == pytest.approx(0.5) and quotient.met() == "missed"
    absolute = timing.Row(timing.Spec("a", ours, None, None, kind=timing.ABSOLUTE, goal=10.0), 1)
    absolute.ours = [9e-6]
    assert absolute.met() == "met" and absolute.cells()[1:4] == ["-", "-", "optraj <= 10 us"]
    absent = timing.Row(timing.Spec("p", ours, other, "pink not installed"), 1)
    absent.ours = [9e-6]
    assert absent.cells()[1:5] == [
        "peer not installed (pink not installed)",
        "-",
        "peer / optraj >= 1",
        "-",
    ]


def test_a_peer_whose_module_is_absent_is_named_missing(monkeypatch):
    calls = _load("peer_calls", monkeypatch)
    monkeypatch.setitem(calls.MODULES, "absent", ("numpy", "no_such_module_35"))
    assert calls.missing("absent") == "no_such_module_35 not installed"
    monkeypatch.setitem(calls.MODULES, "present", ("numpy",))
    assert calls.missing("present") is None


def test_the_raw_toppra_paths_are_optrajs_curves(monkeypatch):
    import toppra

    from optraj.planners.time_optimal.toppra_path import GeometricPath

    calls = _load("peer_calls", monkeypatch)
    rng = np.random.default_rng(35)
    for _ in range(5):
        points = rng.uniform(-2.0, 2.0, (4, 7))
        for ours, make in (
            (GeometricPath.pchip(points), calls._pchip_path),
            (GeometricPath.spline(points), toppra.SplineInterpolator),
        ):
            theirs = make(ours.knots, points)
            s = np.linspace(ours.knots[0], ours.knots[-1], 57)
            assert np.allclose(theirs.path_interval, ours.knots[[0, -1]], rtol=0, atol=0)
            for order in (0, 1, 2):
                assert np.allclose(theirs(s, order), ours.native(s, order), rtol=1e-9, atol=1e-9)
