"""``optraj demo``: the Sawyer pool shot, from the planners to where the ball went.

It plans the pool shot (cue at 1 m/s) with every pool-shot planner and says, one line each,
what each did and why (:mod:`optraj.demo_shot`); tracks the minimum-time optimal-control plan
with the pseudo-inverse PID and the differential-IK QP; strikes the ball in MuJoCo and says
where it went; gives the checker's verdicts on the other tasks (the youBot pick and place, the
ECE486 paddle task) in a few lines; writes plots (PNG) and plans (JSON) to the output folder;
and ends with which files to open next. The robots' joint and limit tables are
``optraj robots NAME``.

Everything heavy is imported inside the functions, so that ``import optraj`` stays cheap.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any, TextIO

from optraj.cli_output import output_folder
from optraj.demo_shot import (
    ball_section,
    plan_every_planner,
    planner_section,
    short_reason,
    tracking_section,
)
from optraj.errors import MissingDependencyError

__all__ = ["Progress", "run", "short_reason", "viewer_file", "write_plots"]

#: The shot every planner plans [m/s].
SHOT_SPEED = 1.0
#: Steps the progress bar counts: 8 planners, 3 tracking steps, 3 strikes, 2 tasks, files.
STEPS = 17


class Progress:
    """The demo's progress bar on stderr: tqdm, on a terminal only, gone when done.

    Call it with what is being done now; each call counts one step of ``total``.
    """

    def __init__(self, total: int = STEPS, stream: TextIO | None = None) -> None:
        from tqdm import tqdm

        # disable=None: drawn only when the stream is a terminal (no carriage return in a pipe).
        self._bar: Any = tqdm(
            total=total, file=stream if stream is not None else sys.stderr, disable=None,
            leave=False, dynamic_ncols=True,
            bar_format="{desc} {bar} {n_fmt}/{total_fmt} {elapsed}<{remaining}",
        )  # fmt: skip
        self._started = False

    def __call__(self, message: str) -> None:
        """Show ``message`` as the step now being done (the one before it is finished)."""
        if self._started:
            self._bar.update(1)
        self._started = True
        self._bar.set_description_str(message)

    def done(self) -> None:
        """Clear the bar."""
        self._bar.close()


def run(args: argparse.Namespace, out: TextIO) -> int:
    """Run the whole demo; returns the exit status."""
    from optraj import problems

    out_dir = output_folder(args.out)
    progress = Progress()
    try:
        problem = problems.sawyer_pool_shot(speed=SHOT_SPEED)
        x, y, z = problem.ball
        out.write(
            f"optraj demo: a Sawyer arm strikes a pool ball with a cue, {SHOT_SPEED:g} m/s through "
            f"the ball at ({x:.2f}, {y:.2f}, {z:.2f}) m\n"
        )
        attempts = plan_every_planner(problem, progress)
        planner_section(problem, attempts, out)
        tracked, runs = tracking_section(problem, progress, out)
        ball = None if tracked is None else ball_section(problem, tracked, progress, out)
        carried = _other_tasks(progress, out)
        progress("writing plots and plans")
        plans = {a.key: a.traj for a in attempts if a.traj is not None}
        written = _write_files(out_dir, problem, plans, tracked, runs, ball, out)
        page = viewer_file(out_dir / "pick-and-place.html", *carried, None)
        written += [] if page is None else [page]
    finally:
        progress.done()
    _next_files(out_dir, written, out)
    return 0


def _other_tasks(progress: Any, out: TextIO) -> tuple[Any, Any]:
    """The checker's verdict on the youBot pick and place and the ECE486 paddle task.

    Returns the pick-and-place problem and its quintic plan, for the 3-D view.
    """
    from optraj import planners, problems
    from optraj.cli import describe_failures

    out.write("\nother tasks, judged by the same checker\n")
    progress("the youBot pick and place")
    task = problems.youbot_two_blocks(with_scene=True)
    plans = {}
    for planner in (planners.Quintic(), planners.LSPB()):
        traj = plans[planner.name] = planners.PickAndPlacePlanner(planner, vertical=True).plan(task)
        quantities = QUANTITIES_OF.get(planner.name)
        report = planners.check(traj, task, quantities=quantities)
        verdict = "ok" if report.ok else f"FAIL: {describe_failures(report)}"
        out.write(
            f"  youBot pick and place of two blocks over their table, {planner.name} phases: "
            f"{traj.duration:.3f} s, {verdict}\n"
        )
    progress("the ECE486 paddle task")
    paddle = problems.ece486_paddle_strike()
    traj = planners.Cubic().plan(paddle)
    report = planners.check(traj, paddle)
    end = ", ".join(f"{v:.4f}" for v in traj.sample(traj.duration).q)
    x, y, z = paddle.ball
    out.write(
        f"  the ECE486 paddle task (paddle4 to the ball at ({x:g}, {y:g}, {z:g}) m, cubic, "
        f"{traj.duration:g} s): ends at q = ({end}), {'ok' if report.ok else 'FAIL'}\n"
    )
    return task, plans["quintic"]


#: What the pick-and-place plans are checked for: LSPB has no jerk to speak of.
QUANTITIES_OF = {"lspb": ("position", "velocity", "acceleration")}


def _write_files(
    out_dir: Path,
    problem: Any,
    plans: dict[str, Any],
    tracked: Any,
    runs: list[Any],
    ball: Any,
    out: TextIO,
) -> list[Path]:
    """Write the plots, the plans (JSON, tagged for ``optraj check``) and the viewer file."""
    from optraj.cli import tag_trajectory

    files = {f"plan-{key}.json": traj for key, traj in plans.items()}
    if tracked is not None:
        tag = {"limit_scale": 0.8}
        files["plan-optimal-control-tracked.json"] = tracked
    written = write_plots(out_dir, problem.robot, plans, runs, out)
    for name, traj in files.items():
        options = {"speed": SHOT_SPEED, **(tag if traj is tracked else {})}
        tag_trajectory(traj, "sawyer", "pool-shot", options)
        path = out_dir / name
        traj.to_json(path)
        written.append(path)
    viewer = viewer_file(out_dir / "pool-shot.html", problem, tracked, ball)
    if viewer is not None:
        written.append(viewer)
    return written


def viewer_file(path: Path, problem: Any, traj: Any, outcome: Any) -> Path | None:
    """Write the 3-D view of a task (a self-contained HTML file) and return its path.

    The robot with its tool and the task's scene (the table, the ball and its path; or the
    blocks), animated along ``traj`` (:func:`optraj.viz.write_html`). Returns None, writing
    nothing, when the ``viz`` extra (meshcat) is not installed.
    """
    from optraj import viz

    try:
        return viz.write_html(path, problem.robot, traj, problem=problem, outcome=outcome)
    except MissingDependencyError:
        return None


def _next_files(out_dir: Path, written: list[Path], out: TextIO) -> None:
    """Which files to open next."""
    plots = [p.name for p in written if p.suffix == ".png"]
    plans = [p.name for p in written if p.suffix == ".json"]
    pages = [p.name for p in written if p.suffix == ".html"]
    out.write(f"\nopen next (in {out_dir}/)\n")
    if pages:
        out.write(f"  3-D views, in a browser: {', '.join(pages)}\n")
    if plots:
        out.write(f"  plots: {', '.join(plots)}\n")
    if plans:
        out.write(f"  plans, to check again with optraj check FILE: {', '.join(plans)}\n")
    out.write(
        "  README.md: 'A short tour', 'Using a trajectory', 'Where the ball goes: MuJoCo', "
        "'A 3-D view', 'Results'\n"
        "  notebooks/01_profiles.ipynb, notebooks/02_pool_strike.ipynb, "
        "notebooks/03_paddle_and_pick.ipynb\n"
        "  the robots' joints and limits: optraj robots NAME\n"
    )


def write_plots(
    out_dir: Path, robot: Any, plans: dict[str, Any], runs: list[Any], out: TextIO
) -> list[Path]:
    """Write ``profiles.png``, ``tool_speed.png`` and ``tracking.png``; returns the paths.

    Without matplotlib, prints one line saying the plots were skipped and returns [].
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from optraj import controllers
        from optraj.planners import plot as plotting
    except ImportError:
        out.write("\nplots skipped: matplotlib is not installed (pip install 'optraj[examples]')\n")
        return []
    figures = []
    try:
        if plans:
            figures.append(("profiles.png", plotting.plot_profiles(plans, robot.limits)))
            figures.append(("tool_speed.png", plotting.plot_tool_speed(robot, plans)))
        if runs:
            figures.append(("tracking.png", controllers.plot_tracking(runs, robot.limits)))
    except MissingDependencyError:
        out.write("\nplots skipped: matplotlib is not installed (pip install 'optraj[examples]')\n")
        return []
    written: list[Path] = []
    for name, figure in figures:
        path = out_dir / name
        figure.savefig(path, dpi=110)
        plt.close(figure)
        written.append(path)
    return written
