"""Random piecewise polynomials: the checker never misses a breach that dense sampling
sees, reports no NaN at any rate, and a trajectory survives export and import unchanged."""

from __future__ import annotations

import itertools
import json

import numpy as np
from conftest import get_robot
from hypothesis import given, note, settings
from hypothesis import strategies as st

from fuzz.budget import examples, recorded
from fuzz.oracles import assert_nan_free
from fuzz.strategies import polynomial_trajectories, robot_names
from optraj import planners
from optraj.errors import OptrajError

#: Dense samples per segment for the independent look at the peaks.
DENSE = 2001
#: A sampled peak above the limit by more than this [-] must be a failing finding.
SLACK = 1e-6


@st.composite
def _cases(draw: st.DrawFn) -> tuple[str, dict, float]:
    robot = draw(robot_names)
    rate = draw(st.sampled_from((1000.0, 250.0, 50.0, 1.0)) | st.floats(1.0, 5000.0))
    return robot, draw(polynomial_trajectories(robot)), rate


def _dense_ratio(traj: planners.Trajectory, limits, order: int) -> float:
    """The largest |derivative| / limit over dense samples of every segment."""
    knots = np.asarray(traj.breakpoints)
    times = np.concatenate([np.linspace(a, b, DENSE)[:-1] for a, b in itertools.pairwise(knots)])
    sample = traj.sample(times)
    values = (sample.qd, sample.qdd)[order - 1]
    limit = (limits.velocity, limits.acceleration)[order - 1]
    return float(np.max(np.abs(values) / limit))


@settings(max_examples=examples("trajectory", 2))
@given(case=_cases())
@recorded
def test_the_checker_sees_every_breach_that_dense_sampling_sees(case):
    robot_name, arguments, rate = case
    robot = get_robot(robot_name)
    traj = planners.Trajectory(**arguments, joint_names=robot.joint_names)
    try:
        report = planners.check(traj, robot, rate=rate, quantities=("velocity", "acceleration"))
    except OptrajError as exc:  # e.g. a rate too high for the duration
        return type(exc).__name__
    assert_nan_free([(f.name, f.value, f.limit, f.margin, f.ratio) for f in report.findings], "")
    note(report.summary())
    for order, name in ((1, "velocity"), (2, "acceleration")):
        sampled = _dense_ratio(traj, robot.limits, order)
        finding = report[name]
        assert finding.ratio >= sampled * (1.0 - 1e-9) - 1e-12, (
            f"{name}: the checker's worst ratio {finding.ratio:.9g} is below the sampled "
            f"{sampled:.9g}"
        )
        if sampled > 1.0 + SLACK:
            assert not finding.ok, f"{name} peaks at {sampled:.6g} of its limit and passes"
    return "breach" if not report.ok else "within"


@settings(max_examples=examples("trajectory", 2))
@given(case=_cases())
@recorded
def test_a_trajectory_survives_export_and_import(case):
    robot_name, arguments, rate = case
    robot = get_robot(robot_name)
    traj = planners.Trajectory(
        **arguments, joint_names=robot.joint_names, metadata={"robot": robot_name}
    )
    for copy in (
        planners.Trajectory.from_dict(traj.to_dict()),
        planners.Trajectory.from_json(traj.to_json()),
        planners.Trajectory.from_dict(json.loads(json.dumps(traj.to_dict()))),
    ):
        assert np.array_equal(copy.breakpoints, traj.breakpoints)
        assert np.array_equal(copy.coefficients, traj.coefficients)
        assert copy.joint_names == traj.joint_names
        assert copy.metadata.get("robot") == robot_name
    try:
        arrays = traj.to_arrays(rate)
    except OptrajError as exc:
        return type(exc).__name__
    assert_nan_free(arrays, "to_arrays")
    return "round trip"
