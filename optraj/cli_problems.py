"""The problems of ``optraj plan`` and ``optraj check``: their names, robots and options.

:func:`build_problem` makes a problem from its command-line name and JSON-able options (the
ones ``optraj plan`` records in a trajectory's metadata, so that ``optraj check`` rebuilds
the same problem).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from optraj.errors import InvalidInputError, OptrajError, UnknownNameError

__all__ = ["PROBLEMS", "build_problem", "check_fit", "joint_words"]

#: The problems ``optraj plan`` knows, each with the one robot it is for (None: any robot).
PROBLEMS: dict[str, str | None] = {
    "pool-shot": "sawyer",
    "paddle-strike": "paddle4",
    "pick-and-place": "youbot",
    "point-to-point": None,
}


def check_fit(robot: str, problem: str) -> None:
    """Raise unless ``problem`` is known and made for ``robot``."""
    from optraj import robots

    if robot not in robots.known_robots():
        raise UnknownNameError("robot", robot, robots.known_robots())
    if problem not in PROBLEMS:
        raise UnknownNameError("problem", problem, PROBLEMS)
    wanted = PROBLEMS[problem]
    if wanted is not None and wanted != robot:
        fits = [name for name, owner in PROBLEMS.items() if owner in (None, robot)]
        raise InvalidInputError(
            f"problem {problem!r} is for robot {wanted!r}, not {robot!r}; problems for "
            f"{robot}: {', '.join(fits)}",
            name="problem",
        )


def _joint_values(robot: Any, values: Any, option: str) -> list[float]:
    """Joint positions [rad or m] from a pose name or a list of one number per joint.

    Numbers are numbers here (a bool, or a string from a file, is refused): the words of the
    command line are parsed by :func:`joint_words` first.
    """
    from optraj.validation import as_vector

    if isinstance(values, str):
        if values not in robot.poses:
            raise InvalidInputError(
                f"{option} takes {robot.dof} joint positions [rad or m] or a pose name "
                f"({', '.join(robot.poses)}), got {values!r}",
                name=option,
            )
        return as_vector(robot.poses[values], option).tolist()
    numbers = as_vector(values, option).tolist()  # refuses NaN, inf, bools, text and nesting
    if len(numbers) != robot.dof:
        raise InvalidInputError(
            f"{option} needs {robot.dof} values [rad or m], one per joint of {robot.name} "
            f"({', '.join(robot.joint_names)}), got {len(numbers)}",
            name=option,
        )
    return numbers


def joint_words(words: Sequence[str], option: str) -> str | list[float]:
    """The words given to ``--q-start`` or ``--q-goal``: one pose name, or numbers [rad or m].

    The numbers may be separate words or separated by commas (``0.1,0.2`` or ``"0.1 0.2"``).
    """
    parts = [part for word in words for part in word.replace(",", " ").split()]
    try:
        return [float(part) for part in parts]
    except ValueError:
        if len(words) == 1:
            return words[0]  # a pose name, looked up with the robot
        raise InvalidInputError(
            f"{option} takes joint positions [rad or m], one per joint, or one pose name, got "
            f"{' '.join(words)!r}",
            name=option,
        ) from None


#: An option's value by name (None when missing or None).
Getter = Callable[..., Any]


def _number(get: Getter, key: str, default: float, unit: str) -> float:
    """An option that is one number (a bool or a string of a file is refused)."""
    from optraj.validation import as_number

    return as_number(get(key, default), f"--{key}", unit)


def _pool_shot(get: Getter) -> Any:
    from optraj import problems
    from optraj.validation import as_vector

    extra: dict[str, Any] = {}
    if get("ball") is not None:
        extra["ball"] = tuple(as_vector(get("ball"), "--ball", 3))
    return problems.sawyer_pool_shot(
        speed=_number(get, "speed", 1.0, "m/s"),
        heading_deg=_number(get, "heading", 0.0, "deg"),
        **extra,
    )


def _paddle_strike(get: Getter) -> Any:
    from optraj import problems, robots
    from optraj.problems.scenarios import ECE486_PADDLE_BALLS
    from optraj.validation import as_vector

    return problems.PaddleStrike(
        robots.load("paddle4"),
        ball=as_vector(get("ball", ECE486_PADDLE_BALLS[0]), "--ball", 3),
        speed=_number(get, "speed", 0.0, "m/s"),
    )


def _point_to_point(robot: str, get: Getter) -> Any:
    import numpy as np

    from optraj import problems, robots
    from optraj.validation import as_duration

    model = robots.load(robot)
    duration = get("duration")
    built = problems.PointToPoint(
        model,
        q_start=np.array(_joint_values(model, get("q_start", "home"), "--q-start")),
        q_goal=np.array(_joint_values(model, get("q_goal", "home"), "--q-goal")),
        duration=None if duration is None else as_duration(duration, "--duration"),
    )
    if built.duration is None and built.still:  # the one still-move rule
        raise InvalidInputError(
            "the goal equals the start (--q-start and --q-goal default to home): give "
            f"--q-goal as {model.dof} joint positions [rad or m]{_other_poses(model, built)}, "
            "or a --duration to hold still",
            name="q_goal",
        )
    return built


def _other_poses(robot: Any, problem: Any) -> str:
    """`` or a pose name (a, b)`` for the named poses away from the start; ``""`` if none.

    A pose that only renames the start (Sawyer's ``neutral`` is its ``home``) is no way out.
    """
    import numpy as np

    names = [
        name
        for name, q in robot.poses.items()
        if not np.allclose(q, problem.q_start, rtol=0.0, atol=1e-12)
    ]
    return f" or a pose name ({', '.join(names)})" if names else ""


def _youbot_blocks(get: Getter) -> Any:
    from optraj import problems

    return problems.youbot_two_blocks()


def build_problem(robot: str, problem: str, options: Mapping[str, Any]) -> Any:
    """Build a problem from its command-line name and JSON-able options.

    Args:
        robot: Robot name.
        problem: One of :data:`PROBLEMS`.
        options: ``speed`` [m/s], ``ball`` [m], ``heading`` [deg] (strikes); ``q_start``,
            ``q_goal`` (a pose name or one number per joint [rad or m]), ``duration`` [s]
            (point-to-point); ``limit_scale`` [-] (all). Missing or None: the default. Numbers
            must be numbers (bools and strings are refused).

    Raises:
        UnknownNameError, InvalidInputError: An unknown name, a problem for another robot, or
            bad option values.
    """
    from optraj.validation import as_fraction

    check_fit(robot, problem)
    if not isinstance(options, Mapping):
        raise InvalidInputError(
            f"options must be a mapping of option names to values, got {type(options).__name__}",
            name="options",
        )
    get = {key: value for key, value in options.items() if value is not None}.get
    # The ranges of speed, ball and heading are the problems' to check; here their types.
    scale = as_fraction(get("limit_scale", 1.0), "--limit-scale")
    try:
        if problem == "point-to-point":
            built = _point_to_point(robot, get)
        else:
            builders = {
                "pool-shot": _pool_shot,
                "paddle-strike": _paddle_strike,
                "pick-and-place": _youbot_blocks,
            }
            built = builders[problem](get)
        if scale != 1.0:
            built = dataclasses.replace(built, limits=built.robot.limits.scaled(scale))
    except OptrajError:
        raise
    except (TypeError, ValueError, KeyError) as exc:  # a problem's own untyped refusal
        raise InvalidInputError(
            f"bad options for problem {problem!r}: {exc}", name="options"
        ) from exc
    return built
