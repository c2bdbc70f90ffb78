"""Every benchmark in one run: time-optimal profiles, pool strikes, tracking; tables and plots.

Runs ``time_optimal.py``, ``strike.py``, ``tracking.py``, ``outcome.py``, ``sweep.py``,
``peers.py`` and ``clearance.py`` (each writes its Markdown table into the output folder;
``outcome.py`` also draws ``outcome_paths.png`` and ``outcome_heading.png``), then draws the
plots (PNG) of the pool shot:

* ``profiles.png``: the busiest joint of a Sawyer move by every joint-space planner;
* ``strike_speed.png``: the cue tip speed of every strike planner that plans the shot;
* ``tracking.png``: the pseudo-inverse and the QP following the minimum-time strike.

With ``--readme`` it then rewrites the README's results section (between its two markers)
from the tables just written, so that the README's numbers are never typed by hand.

Without ``--out`` everything goes to a new temporary folder (printed at the end), so that a
run never rewrites the committed ``benchmarks/results/``; ``make bench`` passes
``--out benchmarks/results --readme``.

Usage: ``python benchmarks/run_all.py [--quick] [--out DIR] [--readme]``
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import clearance
import outcome
import peers
import strike
import sweep
import time_optimal
import tracking

from optraj import controllers, planners, problems
from optraj.errors import OptrajError

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
README = ROOT / "README.md"
BEGIN = "<!-- results: written by `make bench` (benchmarks/run_all.py --readme); do not edit -->"
END = "<!-- end of results -->"

#: (name, main, extra arguments) of each benchmark, in run order.
BENCHMARKS: list[tuple[str, Callable[[list[str]], int], list[str]]] = [
    ("time_optimal", time_optimal.main, []),
    ("strike", strike.main, []),
    ("tracking", tracking.main, []),
    ("outcome", outcome.main, []),
    ("sweep", sweep.main, []),
    ("peers", peers.main, []),
    ("clearance", clearance.main, []),
]


def run_benchmarks(out: Path, quick: bool) -> None:
    """Run every benchmark, each writing ``<name>.md`` into ``out``.

    Each one starts with a line on stderr (which one, how long the run has taken so far); the
    benchmarks draw their own progress bars.

    Raises:
        RuntimeError: A benchmark returned a non-zero status.
    """
    started = time.perf_counter()
    for index, (name, main, extra) in enumerate(BENCHMARKS):
        elapsed = time.perf_counter() - started
        print(
            f"benchmark {index + 1}/{len(BENCHMARKS)}: {name} (after {elapsed:.0f} s)",
            file=sys.stderr,
            flush=True,
        )
        arguments = [*extra, "--out", str(out / f"{name}.md")]
        if quick:
            arguments.append("--quick")
        status = main(arguments)
        if status != 0:
            raise RuntimeError(f"benchmark {name} exited with status {status}")


def draw_plots(out: Path) -> list[Path]:
    """Draw the PNG plots of the pool shot into ``out``; returns the files written.

    Besides the three plots above, ``limit_fractions.png``: every joint of three strikes
    (pull back + line, Ruckig, minimum-time optimal control) as a fraction of its limits.
    """
    import matplotlib

    matplotlib.use("Agg")
    from optraj.planners.plot import (
        plot_limit_fractions,
        plot_profiles,
        plot_tool_speed,
        pyplot,
    )

    plt = pyplot()
    shot = problems.sawyer_pool_shot(speed=1.0)
    robot = shot.robot
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.4)
    joint_plans = {}
    for label, planner in [
        ("cubic", planners.Cubic()),
        ("LSPB", planners.LSPB()),
        ("TOPPRA", planners.Toppra()),
        ("Ruckig", planners.Ruckig()),
        ("optimal control", planners.OptimalControl("time")),
    ]:
        joint_plans[label] = planner.plan(move)
    strikes = {}
    for label, planner in strike.planners_to_compare():
        try:
            strikes[label] = planner.plan(shot)
        except OptrajError:
            continue  # the table says why
    fastest = strikes["optimal control (min time)"]
    runs = [
        controllers.simulate(robot, fastest, make(robot))
        for make in (controllers.PseudoInversePID, controllers.DiffIKQP)
    ]
    compared = ("pull-back + line", "ruckig strike", "optimal control (min time)")
    figures = {
        "profiles.png": plot_profiles(joint_plans, robot.limits),
        "strike_speed.png": plot_tool_speed(robot, strikes),
        "tracking.png": controllers.plot_tracking(runs, robot.limits),
        "limit_fractions.png": plot_limit_fractions(
            {label: strikes[label] for label in compared if label in strikes},
            robot.limits,
            robot=robot,
            rate=500.0,
        ),
    }
    written = []
    for name, figure in figures.items():
        path = out / name
        figure.savefig(path, dpi=110)
        plt.close(figure)
        written.append(path)
    return written


def first_table(markdown: str, after: str = "") -> str:
    """The first Markdown table in ``markdown`` after the line that starts with ``after``."""
    lines = markdown.splitlines()
    start = next((k for k, line in enumerate(lines) if line.startswith(after)), 0) if after else 0
    table: list[str] = []
    for line in lines[start:]:
        if line.startswith("|"):
            table.append(line)
        elif table:
            break
    if not table:
        raise ValueError(f"no Markdown table after {after!r}")
    return "\n".join(table)


def results_section(out: Path, plots: Path) -> str:
    """The README's results section, from the tables in ``out``; images linked from ``plots``."""
    read = {name: (out / f"{name}.md").read_text() for name, _, _ in BENCHMARKS}
    command = {name: re.search(r"Command: `([^`]*)`", read[name]) for name in read}
    cite = {name: (m.group(1) if m else f"benchmarks/{name}.py") for name, m in command.items()}
    return "\n".join(
        [
            BEGIN,
            "",
            f"**Pool strikes on Sawyer** (`{cite['strike']}`; details in "
            "`benchmarks/results/strike.md`):",
            "",
            first_table(read["strike"]),
            "",
            f"**Tracking those strikes** (`{cite['tracking']}`; details in "
            "`benchmarks/results/tracking.md`):",
            "",
            first_table(read["tracking"]),
            "",
            first_table(read["tracking"], "## Controller time per step"),
            "",
            f"![The pseudo-inverse and the QP following the minimum-time strike]({plots}/"
            "tracking.png)",
            "",
            f"**Where the ball goes** (`{cite['outcome']}`; every planner, controller and "
            "condition in `benchmarks/results/outcome.md`): the targets against this run,",
            "",
            first_table(read["outcome"], "## Targets"),
            "",
            f"![Balls seen from above, tracked by each controller]({plots}/outcome_paths.png)",
            "",
            f"![Heading-error distribution per controller and condition]({plots}/"
            "outcome_heading.png)",
            "",
            f"**Durations against the lower bound** (`{cite['time_optimal']}`; details in "
            "`benchmarks/results/time_optimal.md`):",
            "",
            first_table(read["time_optimal"], "## Durations"),
            "",
            f"**Sweeps: shots per second against workers** (`{cite['sweep']}`; details in "
            "`benchmarks/results/sweep.md`):",
            "",
            first_table(read["sweep"], "## Throughput"),
            "",
            "A million-shot map, from the measured cost per shot:",
            "",
            first_table(read["sweep"], "## A million shots"),
            "",
            f"**Against the peers, side by side** (`{cite['peers']}`; each row's peer and "
            "what its ratio divides in `benchmarks/results/peers.md`):",
            "",
            first_table(read["peers"]),
            "",
            f"**What the scene costs** (`{cite['clearance']}`; details in "
            "`benchmarks/results/clearance.md`): the clearance check against the rest of the "
            "checker, and pick-and-place with and without the scene,",
            "",
            first_table(read["clearance"]),
            "",
            first_table(read["clearance"], "## Pick-and-place"),
            "",
            END,
        ]
    )


def rewrite_readme(readme: Path, section: str) -> None:
    """Replace the text between the README's markers (markers included) with ``section``.

    Raises:
        ValueError: The README lacks the markers.
    """
    text = readme.read_text()
    begin, end = text.find(BEGIN), text.find(END)
    if begin < 0 or end < begin:
        raise ValueError(f"{readme} has no results markers ({BEGIN!r} ... {END!r})")
    readme.write_text(text[:begin] + section + text[end + len(END) :])


def output_folder(given: Path | None) -> Path:
    """The folder the run writes to: ``given`` (created if needed), else a new temporary one."""
    if given is None:
        return Path(tempfile.mkdtemp(prefix="optraj-bench-"))
    given.mkdir(parents=True, exist_ok=True)
    return given


def main(argv: list[str] | None = None) -> int:
    """Run every benchmark, draw the plots, optionally rewrite the README."""
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="few cases only (for CI)")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="folder for tables and plots (default: a new temporary folder; make bench "
        f"passes {RESULTS.relative_to(ROOT)})",
    )
    parser.add_argument(
        "--readme", action="store_true", help="rewrite the README's results section"
    )
    args = parser.parse_args(argv)
    started = time.perf_counter()
    out = output_folder(args.out)
    run_benchmarks(out, args.quick)
    for path in draw_plots(out):
        print(f"wrote {path}")
    if args.readme:
        folder = out.resolve()
        images = folder.relative_to(ROOT) if folder.is_relative_to(ROOT) else folder
        rewrite_readme(README, results_section(out, images))
        print(f"rewrote the results section of {README}")
    print(f"all benchmarks in {time.perf_counter() - started:.0f} s; tables and plots in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
