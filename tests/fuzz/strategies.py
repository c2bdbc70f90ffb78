"""Hypothesis strategies: robots, limits, problems, planners, trajectories, controller settings.

Strategies draw plain data (robot names, lists of floats, keyword dictionaries) wrapped in
small specs whose ``build()`` makes the objects, so that hypothesis's falsifying example is a
reproducer that reads as code: the robot, the planner, every input. A spec's ``build()`` may
raise an ``OptrajError`` (a problem that the library refuses is a valid outcome).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from conftest import get_robot
from hypothesis import strategies as st

from optraj import controllers, planners, problems, robots

__all__ = [
    "BASIC",
    "PLANNERS",
    "PROMISES",
    "ROBOTS",
    "ControllerSpec",
    "PlannerSpec",
    "ProblemSpec",
    "bad_values",
    "cartesian_lines",
    "configurations",
    "controller_specs",
    "finite_everywhere",
    "limit_scales",
    "paddle_strikes",
    "point_to_points",
    "polynomial_trajectories",
    "refused_point_to_points",
    "robot_names",
    "waypoint_problems",
]

#: The robots of the suite: the three shipped ones, then example-robot-data's when installed.
ROBOTS: tuple[str, ...] = ("paddle4", "sawyer", "youbot") + (
    ("panda", "ur5") if importlib.util.find_spec("example_robot_data") is not None else ()
)
#: The symmetric limits a scale applies to.
SCALED = ("velocity", "acceleration", "jerk")

robot_names = st.sampled_from(ROBOTS)


def _floats(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@dataclass(frozen=True)
class ProblemSpec:
    """A problem as data: ``problems.<kind>(load(robot), **fields, limits=scaled limits)``.

    Attributes:
        robot: Robot name.
        kind: Class name in :mod:`problems`, e.g. ``"PointToPoint"``.
        fields: Keyword arguments besides robot and limits (lists of floats, numbers).
        scale: Per-joint factors [-] of the velocity, acceleration and jerk limits, in (0, 1];
            the robot's limits when empty.
    """

    robot: str
    kind: str
    fields: dict[str, Any]
    scale: dict[str, tuple[float, ...]] = field(default_factory=dict)

    def limits(self) -> robots.JointLimits:
        """The scaled limits."""
        base = get_robot(self.robot).limits
        return dataclasses.replace(
            base, **{name: getattr(base, name) * np.array(f) for name, f in self.scale.items()}
        )

    def build(self) -> Any:
        """The problem (raises the library's error when it refuses the inputs)."""
        extra = {"limits": self.limits()} if self.scale else {}
        return getattr(problems, self.kind)(get_robot(self.robot), **self.fields, **extra)


@dataclass(frozen=True)
class PlannerSpec:
    """A planner as data: ``planners.<name>(*args, **options)``."""

    name: str
    args: tuple[Any, ...] = ()
    options: dict[str, Any] = field(default_factory=dict)

    def build(self) -> Any:
        """A fresh planner."""
        return getattr(planners, self.name)(*self.args, **self.options)


@st.composite
def limit_scales(draw: st.DrawFn, robot: str, smallest: float = 0.05) -> dict[str, tuple]:
    """Per-joint factors of the velocity, acceleration and jerk limits in [smallest, 1].

    One in four draws keeps the robot's limits, one in four scales all joints alike.
    """
    n = get_robot(robot).dof
    how = draw(st.sampled_from(("robot", "uniform", "per joint", "per joint")))
    if how == "robot":
        return {}
    if how == "uniform":
        factor = draw(_floats(smallest, 1.0))
        return {name: (factor,) * n for name in SCALED}
    joint = st.lists(_floats(smallest, 1.0), min_size=n, max_size=n).map(tuple)
    return {name: draw(joint) for name in SCALED}


def configurations(robot: str, margin: float = 0.0) -> st.SearchStrategy[list[float]]:
    """Joint positions within the position limits [rad or m], ``margin`` inside them."""
    limits = get_robot(robot).limits
    return st.tuples(
        *(
            _floats(lo + margin, hi - margin)
            for lo, hi in zip(limits.lower, limits.upper, strict=True)
        )
    ).map(list)


@st.composite
def _goal(draw: st.DrawFn, robot: str, q_start: list[float]) -> list[float]:
    """A goal: anywhere, the start itself, or a tiny step from it (1e-13 .. 1e-3)."""
    how = draw(st.sampled_from(("anywhere", "anywhere", "anywhere", "same", "tiny")))
    if how == "anywhere":
        return draw(configurations(robot))
    if how == "same":
        return list(q_start)
    limits = get_robot(robot).limits
    step = 10.0 ** draw(_floats(-13.0, -3.0))
    sign = np.where(np.asarray(q_start) + step <= limits.upper, 1.0, -1.0)
    return [float(v) for v in np.asarray(q_start) + sign * step]


def _rates(robot: str, quantity: str, fraction: float) -> st.SearchStrategy[list[float]]:
    """Joint rates within ``fraction`` of a limit (e.g. velocities [rad/s or m/s])."""
    bound = getattr(get_robot(robot).limits, quantity) * fraction
    return st.tuples(*(_floats(-b, b) for b in bound)).map(list)


@st.composite
def point_to_points(
    draw: st.DrawFn, robot: str | None = None, moving: bool = False, timed: bool = True
) -> ProblemSpec:
    """A valid PointToPoint: start and goal within the limits, scaled limits.

    With ``moving`` the boundary velocities (and sometimes accelerations) are drawn within
    half their limits (a start near a position limit may then be unplannable: refused).
    With ``timed`` one in three has a fixed duration in [0.01, 30] s.
    """
    name = robot if robot is not None else draw(robot_names)
    q_start = draw(configurations(name))
    fields: dict[str, Any] = {"q_start": q_start, "q_goal": draw(_goal(name, q_start))}
    if moving:
        for key in ("qd_start", "qd_goal"):
            if draw(st.booleans()):
                fields[key] = draw(_rates(name, "velocity", 0.5))
        for key in ("qdd_start", "qdd_goal"):
            if draw(st.integers(0, 3)) == 0:
                fields[key] = draw(_rates(name, "acceleration", 0.5))
    if timed and draw(st.integers(0, 2)) == 0:
        fields["duration"] = draw(_floats(0.01, 30.0))
    return ProblemSpec(name, "PointToPoint", fields, draw(limit_scales(name)))


@st.composite
def refused_point_to_points(draw: st.DrawFn, robots_: Sequence[str] = ROBOTS) -> ProblemSpec:
    """PointToPoints likely to be refused: far moves in very small limits (1e-4 .. 1e-2 of
    the robot's), short fixed durations, or moving ends near a position limit."""
    name = draw(st.sampled_from(tuple(robots_)))
    q_start = draw(configurations(name))
    how = draw(st.sampled_from(("tiny limits", "short duration", "moving at the edge")))
    fields: dict[str, Any] = {"q_start": q_start, "q_goal": draw(configurations(name))}
    scale: dict[str, tuple] = {}
    if how == "tiny limits":
        factor = 10.0 ** draw(_floats(-4.0, -2.0))
        scale = {key: (factor,) * get_robot(name).dof for key in SCALED}
    elif how == "short duration":
        fields["duration"] = 10.0 ** draw(_floats(-4.0, -1.0))
    else:
        limits = get_robot(name).limits
        edge = [float(v) for v in limits.upper]
        fields = {
            "q_start": edge,
            "q_goal": fields["q_goal"],
            "qd_start": [float(v) for v in 0.9 * limits.velocity],
        }
    return ProblemSpec(name, "PointToPoint", fields, scale)


@st.composite
def waypoint_problems(draw: st.DrawFn) -> ProblemSpec:
    """Waypoints: 2 to 5 configurations, sometimes fixed segment times or a via tolerance."""
    name = draw(robot_names)
    count = draw(st.integers(2, 5))
    points = [draw(configurations(name)) for _ in range(count)]
    if draw(st.integers(0, 4)) == 0:
        points[1] = list(points[0])  # a repeated waypoint
    fields: dict[str, Any] = {"waypoints": points}
    if draw(st.integers(0, 3)) == 0:
        fields["segment_durations"] = [draw(_floats(0.05, 10.0)) for _ in range(count - 1)]
    if draw(st.booleans()):
        fields["via_tolerance"] = draw(_floats(1e-6, 0.1))
    return ProblemSpec(name, "Waypoints", fields, draw(limit_scales(name)))


@st.composite
def cartesian_lines(draw: st.DrawFn) -> ProblemSpec:
    """A CartesianLine between the tool poses of two nearby configurations (reachable)."""
    name = draw(robot_names)
    robot = get_robot(name)
    q_start = np.array(draw(configurations(name, margin=0.05)))
    step = np.array(draw(st.lists(_floats(-0.3, 0.3), min_size=robot.dof, max_size=robot.dof)))
    q_goal = robot.limits.clip(q_start + step)
    fields: dict[str, Any] = {
        "T_start": robot.tool_pose(q_start).tolist(),
        "T_goal": robot.tool_pose(q_goal).tolist(),
        "q_start": q_start.tolist(),
    }
    if draw(st.booleans()):
        fields["speed"] = draw(_floats(0.01, 2.0))
    return ProblemSpec(name, "CartesianLine", fields, draw(limit_scales(name, smallest=0.2)))


@st.composite
def paddle_strikes(draw: st.DrawFn) -> ProblemSpec:
    """A PaddleStrike: a ball inside the paddle4 workspace cuboid, angle, speed, time."""
    x, y, z = (draw(_floats(lo, hi)) for lo, hi in robots.PADDLE4_WORKSPACE.values())
    fields = {
        "ball": [x, y, z],
        "contact_angle": draw(_floats(-0.5, 0.5)),
        "speed": draw(st.just(0.0) | _floats(0.0, 2.0)),
        "contact_time": draw(_floats(0.2, 5.0)),
    }
    return ProblemSpec("paddle4", "PaddleStrike", fields, draw(limit_scales("paddle4", 0.2)))


# ----------------------------------------------------------------------- planners by kind

#: The limit quantities each planner promises to keep (the checker judges those).
BASIC = ("position", "velocity", "acceleration")
PROMISES: dict[str, tuple[str, ...]] = {
    "Cubic": BASIC,  # a cubic's acceleration jumps at its ends: jerk unbounded
    "Quintic": (*BASIC, "jerk"),
    "LSPB": BASIC,
    "Ruckig": (*BASIC, "jerk"),
    "Toppra": BASIC,
    "ViaPoints": BASIC,
    "CartesianStraightLine": BASIC,
    "OptimalControl": (*BASIC, "jerk"),
    "TimeOptimalStrike": BASIC,
}

#: Planners of each problem kind, by spec.
PLANNERS: dict[str, tuple[PlannerSpec, ...]] = {
    "PointToPoint": (
        PlannerSpec("Cubic"),
        PlannerSpec("Quintic"),
        PlannerSpec("LSPB"),
        PlannerSpec("Ruckig"),
        PlannerSpec("Ruckig", ("phase",)),
        PlannerSpec("Toppra"),
    ),
    "Waypoints": (
        PlannerSpec("ViaPoints", ("lspb",)),
        PlannerSpec("ViaPoints", ("quintic",)),
        PlannerSpec("Toppra"),
    ),
    "CartesianLine": (
        PlannerSpec("CartesianStraightLine", ("quintic",)),
        PlannerSpec("CartesianStraightLine", ("lspb",)),
    ),
    "PaddleStrike": (
        PlannerSpec("Cubic"),
        PlannerSpec("Quintic"),
        PlannerSpec("TimeOptimalStrike", ("ruckig",)),
    ),
}


# --------------------------------------------------------------------------- trajectories


@st.composite
def polynomial_trajectories(draw: st.DrawFn, robot: str) -> dict[str, Any]:
    """``Trajectory(**drawn)`` arguments: 1-4 segments of degree 0-5 for the robot's joints.

    Coefficients are drawn within a few times the limits so that some break them.
    """
    robot_ = get_robot(robot)
    segments = draw(st.integers(1, 4))
    degree = draw(st.integers(0, 5))
    lengths = [draw(_floats(1e-3, 2.0)) for _ in range(segments)]
    knots = [0.0, *np.cumsum(lengths).tolist()]
    centre = (robot_.limits.lower + robot_.limits.upper) / 2.0
    coefficients = []
    for _ in range(segments):
        rows = [[float(v) for v in centre + draw(_rates(robot, "velocity", 0.2))]]
        for power in range(1, degree + 1):
            row = draw(_rates(robot, ("velocity", "acceleration", "jerk")[min(power, 3) - 1], 2))
            rows.append([v / math.factorial(power) for v in row])
        coefficients.append(rows)
    return {"breakpoints": knots, "coefficients": coefficients}


# ------------------------------------------------------------------ controller settings


@dataclass(frozen=True)
class ControllerSpec:
    """A controller and a closed-loop run as data.

    Attributes:
        robot: Robot name.
        name: Class name in :mod:`controllers`.
        options: Its keyword arguments besides the robot.
        run: Keyword arguments of :func:`controllers.simulate` (``noise`` as Noise fields).
    """

    robot: str
    name: str
    options: dict[str, Any]
    run: dict[str, Any]

    def build(self) -> Any:
        """The controller."""
        return getattr(controllers, self.name)(get_robot(self.robot), **self.options)

    def simulate_options(self) -> dict[str, Any]:
        """Keyword arguments for simulate, with the Noise built."""
        options = dict(self.run)
        if options.get("noise") is not None:
            options["noise"] = controllers.Noise(**options["noise"])
        return options


@st.composite
def controller_specs(draw: st.DrawFn) -> ControllerSpec:
    """A controller with random valid settings and a short simulated run."""
    name = draw(robot_names)
    kind = draw(st.sampled_from(("JointPD", "PseudoInversePID", "DiffIKQP")))
    gain = _floats(0.0, 100.0)
    options: dict[str, Any] = {"kp": draw(gain), "kd": draw(_floats(0.0, 1.0))}
    if kind != "JointPD":
        options["ki"] = draw(_floats(0.0, 20.0))
        options["task"] = draw(st.sampled_from(("pose", "axis")))
        # Damping 0 or at least 1e-6: a tinier one is a known defect (a known case of
        # test_controllers.py) that would stop the property at its first case.
        options["damping"] = draw(st.just(0.0) | _floats(1e-6, 0.1))
    if kind == "DiffIKQP":
        options["velocity_scale"] = draw(_floats(0.05, 1.0))
        options["position_gain"] = draw(_floats(0.05, 1.0))
    run: dict[str, Any] = {
        "dt": draw(st.sampled_from((1e-3, 2e-3, 5e-3))),
        "plant": draw(st.sampled_from(("kinematic", "dynamic"))),
        "latency": draw(st.integers(0, 3)),
        "settle": draw(st.sampled_from((0.0, 0.02))),
    }
    if draw(st.booleans()):
        run["noise"] = {
            "position": draw(_floats(0.0, 1e-3)),
            "velocity": draw(_floats(0.0, 1e-2)),
            "seed": draw(st.integers(0, 2**31 - 1)),
        }
    return ControllerSpec(name, kind, options, run)


# ------------------------------------------------------------------------- bad values

_NUMBERS = (
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    1e-300,
    -1e-300,
    0.0,
    -1.0,
    -0.0,
    0,
    -1,
    -(10**6),
    10**6,
    10**9,
    2**63,
    10**30,
)


def bad_values(size: int | None = None) -> st.SearchStrategy[Any]:
    """Values no public entry should take: bools, strings, None, NaN, inf, extremes, negative
    and huge counts, wrong shapes and types. ``size`` adds vectors of wrong lengths and
    vectors of the right length holding one bad number."""
    options: list[st.SearchStrategy[Any]] = [
        st.booleans(),
        st.sampled_from(("", "2", "nan", "abc", "1e9", "-1", "home")),
        st.text(max_size=4),
        st.none(),
        st.sampled_from(_NUMBERS),
        st.complex_numbers(allow_nan=False, max_magnitude=10),
        st.just([]),
        st.just({}),
        st.just({"a": 1}),
        st.just([[1.0, 2.0], [3.0]]),  # ragged
        st.just(np.zeros((2, 2, 2))),
        st.just(object()),
        st.lists(st.floats(), max_size=3),
    ]
    if size is not None:
        options.append(st.integers(0, 3 * size + 1).filter(lambda k: k != size).map(np.ones))
        options.append(
            st.tuples(st.integers(0, size - 1), st.sampled_from(_NUMBERS[:7]) | st.booleans()).map(
                lambda pair: _one_bad(size, *pair)
            )
        )
    return st.one_of(*options)


def _one_bad(size: int, index: int, value: Any) -> list[Any]:
    values: list[Any] = [0.1] * size
    values[index] = value
    return values


def _children(value: Any, where: str) -> list[tuple[Any, str]]:
    """The parts of a container (dataclass, mapping, sequence) with their paths."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [(getattr(value, f.name), f"{where}.{f.name}") for f in dataclasses.fields(value)]
    if isinstance(value, dict):
        return [(item, f"{where}[{key!r}]") for key, item in value.items()]
    if isinstance(value, (list, tuple)):
        return [(item, f"{where}[{k}]") for k, item in enumerate(value[:10_000])]
    return []


def finite_everywhere(value: Any, where: str = "output", seen: Sequence[int] = ()) -> str | None:
    """Where a NaN hides in ``value`` (arrays, numbers, dataclasses, mappings, sequences).

    Returns:
        A path to the first NaN, e.g. ``"output.metrics.position_rms"``, or None.
    """
    if id(value) in seen:
        return None
    seen = (*seen, id(value))
    if isinstance(value, float):
        return where if math.isnan(value) else None
    if isinstance(value, np.ndarray):
        return where if value.dtype.kind in "fc" and np.isnan(value).any() else None
    for item, path in _children(value, where):
        found = finite_everywhere(item, path, seen)
        if found:
            return found
    return None
