"""Tests of planners.profiles.sequencer: youBot pick-and-place with classic profiles, end to end."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj import problems
from optraj.errors import CollisionError, InvalidInputError
from optraj.planners.checker import check
from optraj.planners.profiles.sequencer import PickAndPlacePlanner
from optraj.planners.profiles.time_scaling import Cubic, Quintic
from optraj.problems.pick_and_place import PHASES, RETREAT
from optraj.problems.scenarios import block_clearance_scene
from optraj.problems.scene_shapes import translation


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


@pytest.fixture(scope="module")
def vertical_plan():
    """The two-block task with its scene, planned with vertical lines (Quintic)."""
    task = problems.youbot_two_blocks(with_scene=True)
    return task, PickAndPlacePlanner(Quintic(), vertical=True).plan(task)


@pytest.mark.slow
def test_with_its_scene_every_link_keeps_2_cm_from_the_blocks_it_does_not_hold(vertical_plan):
    task, traj = vertical_plan
    names = (*PHASES, RETREAT)
    assert [p.name for p in traj.phases] == [f"{name}_{k}" for k in range(2) for name in names]
    # Every finding, the scene's clearance too (nothing that may not touch does).
    report = check(traj, task)
    assert report.ok, report.summary()
    # 2 cm from every block, but for the gripper at the block it goes down on, holds, puts down
    # and rises from, and at the block under it on the pile (block_clearance_scene).
    blocks = block_clearance_scene(task, margin=0.02)
    finding = check(traj, task, scene=blocks, quantities=[])["clearance"]
    assert finding.ok and finding.value >= 0.02, finding.detail


@pytest.mark.slow
def test_the_gripper_goes_down_and_up_vertically(vertical_plan):
    task, traj = vertical_plan
    for k in range(task.count):
        for phase, point in (
            (f"descend_{k}", task.picks[k]),
            (f"release_{k}", task.place_point(k)),
            (f"{RETREAT}_{k}", task.place_point(k)),
        ):
            span = traj.phase(phase)
            times = np.linspace(span.t_start, span.t_end, 41)
            tcp = np.array([task.robot.tool_pose(q)[:3, 3] for q in traj.sample(times).q])
            np.testing.assert_allclose(tcp[:, :2], np.tile(point[:2], (41, 1)), atol=1e-6)
            assert np.ptp(tcp[:, 2]) == pytest.approx(task.clearance, abs=1e-6)


@pytest.mark.slow
def test_a_plan_through_an_obstacle_is_refused_naming_the_pair(vertical_plan):
    task, traj = vertical_plan
    # A ball where the TCP passes half-way through the turn to the pile: every target is
    # clear of it, the move between them is not.
    span = traj.phase("turn_to_target_0")
    q = traj.sample(0.5 * (span.t_start + span.t_end)).q
    ball = problems.Sphere("ball", 0.01, translation(task.robot.tool_pose(q)[:3, 3]))
    scene = task.scene
    blocked = dataclasses.replace(scene, objects=(*scene.objects, ball))
    obstructed = dataclasses.replace(task, scene=blocked)  # keeps the interim pose
    with pytest.raises(CollisionError, match="'ball'") as caught:
        PickAndPlacePlanner(Quintic(), vertical=True).plan(obstructed)
    assert caught.value.second == "ball" and caught.value.distance < 0.0
    assert "(turn_to_target_0)" in caught.value.what


def test_vertical_must_be_a_bool():
    with pytest.raises(InvalidInputError, match="vertical"):
        PickAndPlacePlanner(Quintic(), vertical="yes")  # type: ignore[arg-type]
    assert "vertical lines" in PickAndPlacePlanner(vertical=True).name
