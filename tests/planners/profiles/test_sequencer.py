"""Tests of planners.profiles.sequencer: youBot pick-and-place with classic profiles, end to end."""

from __future__ import annotations

import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.profiles.sequencer import PickAndPlacePlanner
from optraj.planners.profiles.time_scaling import Cubic, Quintic
from optraj.problems.pick_and_place import PHASES


@pytest.mark.parametrize(("profile", "quantities"), [
    (Quintic(), ("position", "velocity", "acceleration", "jerk")),
    (Cubic(), ("position", "velocity", "acceleration")),
])  # fmt: skip
def test_two_blocks_onto_a_pile_within_limits(profile, quantities):
    problem = problems.youbot_two_blocks()
    traj = PickAndPlacePlanner(profile).plan(problem)
    assert [p.name for p in traj.phases] == [f"{name}_{k}" for k in range(2) for name in PHASES]
    report = check(traj, problem, quantities=quantities)
    # Every grasp and release is exactly on its block, gripper down, at rest.
    assert report.ok, report.summary()
    assert sum(f.kind == "task" for f in report.findings) >= 2 + 3 * 2 * 2


def test_rejects_bad_profile_and_problem():
    with pytest.raises(InvalidInputError, match="JointProfile"):
        PickAndPlacePlanner("quintic")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="PickAndPlace"):
        PickAndPlacePlanner().plan(problems.ece486_paddle_strike())
