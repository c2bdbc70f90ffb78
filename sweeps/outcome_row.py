"""Where the ball went: a planned shot tracked in MuJoCo and judged by the ball.

:func:`outcome_columns` runs the project's standard strike recipe on a plan: the
:class:`optraj.controllers.DiffIKQP` controller follows it at 1 kHz on a
:class:`optraj.physics.MujocoPlant` of the shot's scene (:func:`optraj.physics.scene_for`),
for the plan's duration and :data:`SETTLE` s more, and :func:`optraj.physics.outcome` compares
the ball's launch with the commanded shot. It gives the values of
:data:`optraj.sweeps.columns.OUTCOME_COLUMNS`.

An exception while tracking or judging (a paddle strike at speed 0 sends no ball, a
controller that fails) does not lose the planned row: :func:`outcome_columns` records it as
``outcome_error`` and leaves the other outcome columns None. A shot's time limit still
stops it (:class:`optraj.sweeps.time_limit.ShotTimeout` is recorded the same way).

MuJoCo and the controllers are imported on the first outcome, not with the sweeps (a sweep
that does not track its plans starts its workers without them).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from optraj.planners.trajectory import Trajectory
from optraj.problems import PaddleStrike, PoolStrike

if TYPE_CHECKING:
    from optraj.physics import Outcome

__all__ = ["CONTROL_PERIOD", "SETTLE", "outcome_columns", "track"]

#: Control period of the tracking run [s] (1 kHz, as the benchmarks and the README).
CONTROL_PERIOD = 1e-3
#: Time the controller runs on after the plan ends, holding its last pose [s].
SETTLE = 0.05


def track(trajectory: Trajectory, problem: PoolStrike | PaddleStrike) -> Outcome:
    """Track ``trajectory`` with DiffIKQP on the MuJoCo plant of ``problem``; the outcome.

    Raises:
        InvalidInputError: A paddle strike at speed 0 (it sends no ball), or a plan that
            does not fit the problem's robot.
        SolverError: The controller's QP fails.
    """
    from optraj import controllers, physics  # MuJoCo: loaded when a sweep tracks its plans

    robot = problem.robot
    result = controllers.simulate(
        robot,
        trajectory,
        controllers.DiffIKQP(robot),
        CONTROL_PERIOD,
        plant=physics.MujocoPlant(physics.scene_for(problem)),
        settle=SETTLE,
    )
    return physics.outcome(result, problem)


def outcome_columns(
    trajectory: Trajectory, problem: PoolStrike | PaddleStrike
) -> dict[str, object]:
    """The outcome columns of a planned shot (:data:`optraj.sweeps.columns.OUTCOME_COLUMNS`).

    Never raises for the shot's sake: an exception is ``outcome_error`` (``"Type: message"``)
    with ``hit``, ``heading_error``, ``speed_error`` and ``on_target`` None.

    Returns:
        ``hit`` (bool), ``heading_error`` [deg], ``speed_error`` [-], ``on_target`` (bool,
        within :data:`optraj.physics.HEADING_TOLERANCE` deg and
        :data:`optraj.physics.SPEED_TOLERANCE` of the ideal speed), ``outcome_time`` [s]
        and ``outcome_error``.
    """
    start = time.perf_counter()
    columns: dict[str, object] = dict.fromkeys(
        ("hit", "heading_error", "speed_error", "on_target", "outcome_time", "outcome_error")
    )
    try:
        ball = track(trajectory, problem)
    except Exception as exc:  # the plan stays; what stopped its outcome is recorded
        columns["outcome_error"] = f"{type(exc).__name__}: {exc}"
    else:
        columns.update(
            hit=bool(ball.hit),
            heading_error=float(ball.heading_error),
            speed_error=float(ball.speed_error),
            on_target=bool(ball.within),
        )
    columns["outcome_time"] = time.perf_counter() - start
    return columns
