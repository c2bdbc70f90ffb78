"""The ``optraj`` command.

``optraj demo`` runs the main job (:mod:`optraj.demo`): the Sawyer pool shot planned by every
pool-shot planner (what each did and why), tracked by both controllers, struck in MuJoCo (where
the ball went), the checker's verdicts on the other tasks, plots and plans written to ``--out``
and the files to open next. ``optraj plan`` plans one problem with one planner and writes the
trajectory as JSON, CSV or ROS 2 YAML (``--format``), ``optraj check`` judges such a file again,
``optraj bench`` runs the benchmarks of the source checkout into ``--out`` (a new temporary
folder by default), ``optraj robots [NAME ...]`` lists the robots or prints their joints and
limits (:mod:`optraj.cli_robots`), ``optraj map`` sweeps pool shots over the table and draws
their heat maps (:mod:`optraj.cli_map`). ``optraj --version`` prints the installed version.

Errors print one line to stderr (``optraj: error: ...``, led by the option at fault:
:mod:`optraj.cli_errors`) and exit with status 2; ``check`` exits 1 when a trajectory fails.
The packages are imported lazily so that ``optraj --help`` is instant.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import textwrap
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, NoReturn, TextIO

from optraj.errors import InvalidInputError, OptrajError, UnknownNameError

__all__ = [
    "PLANNERS",
    "PROBLEMS",
    "build_problem",
    "describe_failures",
    "main",
    "make_planner",
    "tag_trajectory",
    "version",
]

from optraj.cli_errors import error_line, option_flags
from optraj.cli_map import add_map_parser
from optraj.cli_output import add_output_options, output_file, output_folder, write_output
from optraj.cli_problems import PROBLEMS, build_problem, check_fit, joint_words
from optraj.cli_robots import add_robots_parser


class _Planners(Mapping[str, tuple[str, ...]]):
    """The planners of each problem, by command-line name, from the planner registry.

    Read on first use, so that the command starts without importing the planners.
    """

    def __getitem__(self, problem: str) -> tuple[str, ...]:
        if problem not in PROBLEMS:
            raise KeyError(problem)
        from optraj.planners import registry

        return registry.planner_names(problem)

    def __iter__(self) -> Iterator[str]:
        return iter(PROBLEMS)

    def __len__(self) -> int:
        return len(PROBLEMS)


#: The planners of each problem, by command-line name (from the planner registry).
PLANNERS: Mapping[str, tuple[str, ...]] = _Planners()
#: Options of ``optraj plan`` and the problems they apply to.
_OPTION_PROBLEMS: dict[str, tuple[str, ...]] = {
    "speed": ("pool-shot", "paddle-strike"),
    "ball": ("pool-shot", "paddle-strike"),
    "heading": ("pool-shot",),
    "q_start": ("point-to-point",),
    "q_goal": ("point-to-point",),
    "duration": ("point-to-point",),
}


# ------------------------------------------------------------------------ shared pieces


def version() -> str:
    """The installed distribution's version (its metadata), ``0+unknown`` when not installed."""
    import optraj

    return str(optraj.__version__)


def make_planner(problem: str, name: str) -> Any:
    """The planner called ``name`` on the command line, for a problem of kind ``problem``.

    Raises:
        UnknownNameError: An unknown problem, or a planner that does not plan it (lists the
            ones that do).
    """
    if problem not in PROBLEMS:
        raise UnknownNameError("problem", problem, PROBLEMS)
    from optraj.planners import registry

    return registry.make_planner(problem, name)


def tag_trajectory(traj: Any, robot: str, problem: str, options: Mapping[str, Any]) -> None:
    """Store in the metadata what ``optraj check`` needs to rebuild the problem."""
    traj.metadata.update({"robot": robot, "problem": problem, "problem_options": dict(options)})


def describe_failures(report: Any) -> str:
    """The failing findings of a report, each with its value as % of the limit."""
    parts = []
    for finding in report.violations:
        if math.isinf(finding.ratio):
            parts.append(f"{finding.name} unbounded (jump)")
        else:
            parts.append(f"{finding.name} {finding.ratio:.0%}")
    return ", ".join(parts)


# ------------------------------------------------------------------------------ commands


def _cmd_demo(args: argparse.Namespace, out: TextIO) -> int:
    from optraj import demo

    return demo.run(args, out)


def _plan_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options given for the problem, refusing those that do not apply to it."""
    options: dict[str, Any] = {}
    for key, kinds in _OPTION_PROBLEMS.items():
        value = getattr(args, key)
        if value is None:
            continue
        if args.problem not in kinds:
            raise InvalidInputError(
                f"--{key.replace('_', '-')} does not apply to problem {args.problem!r}; it is "
                f"for {', '.join(kinds)}",
                name=key,
            )
        if key in ("q_start", "q_goal"):
            value = joint_words(value, f"--{key.replace('_', '-')}")
        options[key] = value
    if args.limit_scale != 1.0:
        options["limit_scale"] = args.limit_scale
    return options


def _cmd_plan(args: argparse.Namespace, out: TextIO) -> int:
    robot = args.robot.lower()
    output = output_file(args)  # a bad --format or --rate before anything is planned
    check_fit(robot, args.problem)
    planner = make_planner(args.problem, args.planner)
    options = _plan_options(args)
    problem = build_problem(robot, args.problem, options)
    if args.problem == "point-to-point":
        # Keep the resolved joint positions, so that a pose name or the default rebuilds alike.
        options = {
            "q_start": [float(v) for v in problem.q_start],
            "q_goal": [float(v) for v in problem.q_goal],
            **{k: v for k, v in options.items() if k not in ("q_start", "q_goal")},
        }
    from optraj import planners

    traj = planner.plan(problem)
    tag_trajectory(traj, robot, args.problem, options)
    report = planners.check(traj, problem)
    written = write_output(traj, output, problem.robot)  # a typed error if it cannot
    if len(traj.phases) > 4:
        names = [p.name for p in traj.phases]
        phases = ", ".join([*names[:3], "...", names[-1]])
    else:
        phases = ", ".join(f"{p.name} {p.t_start:.3f}-{p.t_end:.3f} s" for p in traj.phases)
    given = _show(options)
    verdict = (
        f"the checker passes all {len(report.findings)} findings (joint limits including "
        "torque, and every task constraint)"
        if report.ok
        else f"the checker FAILS {len(report.violations)} of {len(report.findings)} findings: "
        f"{describe_failures(report)}"
    )
    solve = traj.metadata.get("solve_time")
    paragraph = (
        f"{args.problem} for {robot}{f' ({given})' if given else ''}, planned with "
        f"{traj.metadata.get('planner', args.planner)}"
        f"{f' in {solve:.2f} s' if isinstance(solve, float) else ''}: a {traj.duration:.3f} s "
        f"motion in {len(traj.phases)} phase{'s' if len(traj.phases) != 1 else ''}"
        f"{f' ({phases})' if phases else ''}; "
        f"{verdict}. {written}"
    )
    out.write(textwrap.fill(paragraph, width=100) + "\n")
    return 0


_UNIT = {"speed": " m/s", "ball": " m", "heading": " deg", "duration": " s"}


def _show(options: Mapping[str, Any]) -> str:
    """Problem options as ``name value unit, ...``."""

    def number(value: Any) -> str:
        return f"{value:.4g}" if isinstance(value, (int, float)) else str(value)

    parts = []
    for key, value in options.items():
        if isinstance(value, (list, tuple)):
            text = "(" + ", ".join(number(v) for v in value) + ")"
        else:
            text = number(value)
        parts.append(f"{key} {text}{_UNIT.get(key, '')}")
    return ", ".join(parts)


def _cmd_check(args: argparse.Namespace, out: TextIO) -> int:
    from optraj import planners, robots
    from optraj.planners.checker import MAX_RATE
    from optraj.validation import as_positive

    # Before the file is read: a bad flag is the first thing to say.
    rate = as_positive(args.rate, "--rate", "Hz", maximum=MAX_RATE)
    # Typed errors for a missing, unreadable, oversized, deeply nested or malformed file.
    try:
        traj = planners.Trajectory.from_json(Path(args.file))
    except InvalidInputError as exc:
        if type(exc) is not InvalidInputError or args.file in str(exc):
            raise
        raise InvalidInputError(f"{args.file!r}: {exc}", name="file", value=args.file) from exc
    saved = traj.metadata.get("robot")
    if saved is not None and not isinstance(saved, str):
        raise InvalidInputError(f"{args.file!r} has a malformed robot name", name="robot")
    robot = (args.robot or saved or "").lower()
    if not robot:
        raise InvalidInputError(
            f"{args.file!r} does not say which robot it is for; give --robot (one of "
            f"{', '.join(robots.known_robots())})",
            name="robot",
        )
    problem_name = traj.metadata.get("problem")
    target: Any
    if problem_name is not None and (saved is None or saved == robot):
        options = traj.metadata.get("problem_options") or {}
        if not isinstance(options, Mapping) or not isinstance(problem_name, str):
            raise InvalidInputError(
                f"{args.file!r} has malformed problem metadata", name="problem_options"
            )
        target = build_problem(robot, problem_name, options)
        against = f"robot {robot}, problem {problem_name}" + (
            f" ({_show(options)})" if options else ""
        )
    else:
        target = robots.load(robot)
        against = f"robot {robot}, its joint limits only (no problem recorded for it)"
    report = planners.check(traj, target, rate=rate)
    out.write(f"{args.file}: checked against {against}\n{report}\n")
    return 0 if report.ok else 1


def _benchmarks_runner() -> Path:
    """Where ``benchmarks/run_all.py`` lies in a source checkout."""
    import optraj

    return Path(optraj.__file__).resolve().parents[1] / "benchmarks" / "run_all.py"


def _bench_folder(given: str | None) -> Path:
    """Where ``optraj bench`` writes: ``given`` (created if needed), else a new temporary folder.

    ``given`` is taken from the caller's directory; the committed ``benchmarks/results/`` is
    written only when named (``make bench`` does).
    """
    import tempfile

    if given is None:
        return Path(tempfile.mkdtemp(prefix="optraj-bench-"))
    return output_folder(given).resolve()


def _cmd_bench(args: argparse.Namespace, out: TextIO) -> int:
    runner = _benchmarks_runner()
    if not runner.is_file():
        raise OptrajError(
            f"the benchmarks ship with the source checkout, not with the installed package: "
            f"{runner} is missing; clone the repository, install it (make demo, or pip install "
            "-e .) and run optraj bench there"
        )
    root = runner.parents[1]
    folder = _bench_folder(args.out)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(root), env.get("PYTHONPATH")]))
    out.flush()
    command = [sys.executable, str(runner), *(["--quick"] if args.quick else [])]
    command += ["--out", str(folder)]
    return subprocess.run(command, cwd=root, env=env, check=False).returncode


# -------------------------------------------------------------------------------- parser


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error message, like the rest of the command.

    ``describe``, when given, writes the description when the help is printed (the plan
    command's lists the planners, which are imported only then).
    """

    def __init__(self, *args: Any, describe: Callable[[], str] | None = None, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.describe = describe

    def format_help(self) -> str:
        if self.describe is not None:
            self.description = self.describe()
        return super().format_help()

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


_UNITS = (
    "Units: positions in rad (revolute joints) or m (prismatic joints and Cartesian points), "
    "times in s, speeds in m/s (tool) or rad/s (joints), angles of --heading in deg."
)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="optraj",
        description=(
            "Optimization-based motion planning for arms that strike and carry. Units: m, rad, "
            "s, rad/s, rad/s^2, rad/s^3, N m (N for prismatic joints)."
        ),
        epilog=(
            "Exit status: 0 done, 1 a checked trajectory fails, 2 bad input or a failed plan "
            "(one line on stderr). 'optraj COMMAND --help' gives each command's units."
        ),
    )
    parser.add_argument(
        "--version",
        action="version",
        version=f"optraj {version()}",
        help="print the installed version and exit",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    _demo_parser(sub)
    add_robots_parser(sub)
    _plan_parser(sub)
    _check_parser(sub)
    bench = sub.add_parser(
        "bench",
        help="run the benchmarks (source checkout only)",
        description=(
            "Run benchmarks/run_all.py of the source checkout with this Python: the time-optimal, "
            "strike, tracking, outcome, sweep and peer benchmarks; tables (Markdown) and plots "
            "(PNG) go to --out, a new temporary folder by default (printed at the end). The "
            "committed benchmarks/results/ and the README's tables are rewritten by 'make bench' "
            "only. Exits with the runner's status, 2 when the benchmarks are not there "
            "(installed package)."
        ),
    )
    bench.add_argument("--quick", action="store_true", help="a few cases only, as in CI")
    bench.add_argument(
        "--out",
        metavar="DIR",
        help="folder for the tables and plots, created if needed (default: a new temporary folder)",
    )
    bench.set_defaults(run=_cmd_bench)
    add_map_parser(sub)
    return parser


def _demo_parser(sub: Any) -> None:
    demo = sub.add_parser(
        "demo",
        help="the pool shot by every planner: what each did and why, tracking, the ball",
        description=(
            "Plan the Sawyer pool shot (cue at 1 m/s) with every pool-shot planner and say in "
            "one line each what it did and why (motion time [s], peaks as a share of the "
            "limits, cue distance from the strike line [mm], or the reason for a refusal); "
            "track the minimum-time optimal-control plan (made within 80 % of the limits) with "
            "the pseudo-inverse PID and the differential-IK QP (errors in mm and %, step time "
            "in us); strike the ball in MuJoCo (heading error [deg], speed error [%], ball "
            "speed [m/s]); give the checker's verdicts on the youBot pick and place and the "
            "ECE486 paddle task; write plots (PNG) and plans (JSON) to --out and say which "
            "files to open next. About 10 s. Joint and limit tables: optraj robots NAME."
        ),
    )
    demo.add_argument(
        "--out",
        default="optraj-out",
        metavar="DIR",
        help="directory for the plots and plans, created if needed (default: ./optraj-out)",
    )
    demo.set_defaults(run=_cmd_demo)


def _plan_description() -> str:
    """The plan command's description: what it does, the problems and their planners, units."""
    lines = [
        textwrap.fill(
            f"{name:<15} robot {robot or 'any'}; planners: {', '.join(PLANNERS[name])}",
            80,
            initial_indent="  ",
            subsequent_indent=" " * 18,
        )
        for name, robot in PROBLEMS.items()
    ]
    intro = (
        "Plan one problem with one planner, check the result and write it as JSON (the exact "
        "piecewise polynomials, with the problem recorded so that 'optraj check' can rebuild "
        "it), or with --format as CSV or a ROS 2 JointTrajectory in YAML sampled at --rate. "
        "Exit status 0 when planned and written (whatever the checker says), 2 when the "
        "input is bad or no plan is possible (one line on stderr)."
    )
    return "\n\n".join(
        [textwrap.fill(intro, 80), "problems:\n" + "\n".join(lines), textwrap.fill(_UNITS, 80)]
    )


def _plan_parser(sub: Any) -> None:
    plan = sub.add_parser(
        "plan",
        help="plan one problem with one planner and write the trajectory (JSON, CSV, ROS YAML)",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        describe=_plan_description,
    )
    plan.add_argument("robot", metavar="ROBOT", help="robot name (see 'optraj robots')")
    plan.add_argument("--problem", required=True, metavar="NAME", help=", ".join(PROBLEMS))
    plan.add_argument(
        "--planner",
        required=True,
        metavar="NAME",
        help="planner name; valid ones per problem above",
    )
    _strike_options(plan)
    _joint_options(plan)
    plan.add_argument(
        "--limit-scale",
        type=float,
        default=1.0,
        metavar="F",
        help="plan within this fraction of the velocity, acceleration and jerk limits, in "
        "(0, 1] (default 1)",
    )
    add_output_options(plan)
    plan.set_defaults(run=_cmd_plan)


def _strike_options(plan: argparse.ArgumentParser) -> None:
    """The options of the strike problems: speed, ball and heading."""
    strike = plan.add_argument_group("pool-shot and paddle-strike")
    strike.add_argument(
        "--speed",
        type=float,
        metavar="M/S",
        help="tool speed at the ball [m/s]: the cue (pool-shot, default 1.0) or the paddle "
        "along its normal (paddle-strike, default 0: arrive at rest)",
    )
    strike.add_argument(
        "--ball",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="ball centre in the base frame [m] (default: pool-shot (0.75, 0.15, -0.05), "
        "paddle-strike the ECE486 paddle task's (1.1, 0.8, 0.7))",
    )
    strike.add_argument(
        "--heading",
        type=float,
        metavar="DEG",
        help="pool-shot direction from +x about +z [deg] (default 0)",
    )


def _joint_options(plan: argparse.ArgumentParser) -> None:
    """The options of point-to-point: start, goal and duration."""
    joint = plan.add_argument_group("point-to-point")
    joint.add_argument(
        "--q-start",
        nargs="+",
        metavar="Q",
        help="start joint positions [rad or m], one per joint (spaces or commas), or a pose "
        "name (default home)",
    )
    joint.add_argument(
        "--q-goal",
        nargs="+",
        metavar="Q",
        help="goal joint positions [rad or m], one per joint (spaces or commas), or a pose name "
        "(default home)",
    )
    joint.add_argument(
        "--duration",
        type=float,
        metavar="S",
        help="fixed duration [s] (ruckig: the shortest; toppra chooses its own); default: as "
        "fast as the limits allow",
    )


def _check_parser(sub: Any) -> None:
    check = sub.add_parser(
        "check",
        help="check a trajectory JSON file against its robot's limits and its problem",
        description=(
            "Check a trajectory written by 'optraj plan' or 'optraj demo' (or "
            "Trajectory.to_json): every joint limit (position [rad or m], velocity, "
            "acceleration, jerk, torque [N m]) and, when the file records its problem, every "
            "task constraint (strike line [m], speed [m/s], ...). Prints the report; exits 0 "
            "when every finding passes, 1 when one fails, 2 on bad input."
        ),
    )
    check.add_argument("file", metavar="FILE", help="trajectory JSON file")
    check.add_argument(
        "--robot",
        metavar="NAME",
        help="robot to check against when the file names none; another robot than the "
        "file's checks its joint limits only",
    )
    check.add_argument(
        "--rate",
        type=float,
        default=1000.0,
        metavar="HZ",
        help="sampling rate [Hz] (breakpoints and exact peaks are always included; default 1000)",
    )
    check.set_defaults(run=_cmd_check)


def _command_parser(parser: argparse.ArgumentParser, command: str) -> argparse.ArgumentParser:
    """The sub-command's own parser (its options name the errors)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            found: argparse.ArgumentParser = action.choices[command]
            return found
    return parser


def main(argv: Sequence[str] | None = None, out: TextIO | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 check failed, 2 bad input)."""
    parser = _parser()
    args = parser.parse_args(argv)
    stream = out if out is not None else sys.stdout
    try:
        return int(args.run(args, stream))
    except (OptrajError, OSError) as exc:
        # Every error a user can cause is an OptrajError; an OSError is a file or folder
        # named on the command line (or the disk) failing outside the library's own checks.
        message = str(exc)
        if isinstance(exc, OSError) and exc.filename is not None:
            message = f"cannot use {str(exc.filename)!r}: {exc.strerror or exc}"
        flags = option_flags(_command_parser(parser, args.command))
        line = error_line(exc, " ".join(message.split()), flags, vars(args))
        print(f"optraj: error: {line}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("optraj: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
