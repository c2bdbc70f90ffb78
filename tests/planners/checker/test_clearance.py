"""The checker's clearance: the right pair and time, a passing case, the bound between samples."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from checker_support import quintic
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.checker.clearance import clearance_pair, joint_reach
from optraj.problems import Attachment, Scene, SceneCollision, Sphere
from optraj.problems.scene_shapes import translation

Q_A = np.array([2.0, 0.6, -1.6, 1.9, 2.9])
Q_B = np.array([3.6, 1.4, -2.2, 2.4, 2.0])
DURATION = 2.0


def _dense(traj, shapes, times):
    """Reference: (smallest distance [m], its time [s], its pair) by brute force."""
    mask = shapes.static_mask()
    shapes.set_active(mask)
    best = []
    for qk in traj.sample(times).q:
        shapes.compute(qk)
        best.append(shapes.smallest(mask))
    k = int(np.argmin([value for _, value in best]))
    return best[k][1], float(times[k]), shapes.pair_names(best[k][0])


def test_a_trajectory_through_an_obstacle_fails_with_its_pair_and_time():
    robot = get_robot("youbot")
    traj = quintic(Q_A, Q_B, DURATION)
    tcp = robot.tool_pose(traj.sample(np.array([1.2])).q[0])[:3, 3]
    scene = Scene((Sphere("post", 0.03, translation(tcp)),))
    finding = planners.check(traj, robot, scene=scene)["clearance"]
    assert not finding.ok and finding.kind == "task" and finding.unit == "m"
    reference, when, pair = _dense(traj, SceneCollision(robot, scene), np.linspace(0, 2, 4001))
    assert finding.value == pytest.approx(reference, abs=2e-4)
    assert abs(finding.time - when) <= 1e-3  # within the sampling step (1 kHz)
    assert pair[1] == "post" and finding.detail.startswith(f"{pair[0]} to post")
    assert finding.margin < 0.0
    assert finding.ratio == pytest.approx(1.0 - finding.value / 0.01)  # finite when overlapping


def test_a_clear_trajectory_passes_and_a_margin_can_fail_it():
    robot = get_robot("youbot")
    traj = quintic(Q_A, Q_B, DURATION)
    scene = Scene((Sphere("post", 0.03, translation((0.0, 0.35, 0.2))),))
    report = planners.check(traj, robot, scene=scene)
    finding = report["clearance"]
    reference, _, _ = _dense(traj, SceneCollision(robot, scene), np.linspace(0, 2, 2001))
    assert finding.ok and finding.value > 0.0
    assert finding.value == pytest.approx(reference, abs=1e-4)
    strict = dataclasses.replace(scene, margin=finding.value + 0.01)
    assert not planners.check(traj, robot, scene=strict)["clearance"].ok
    assert "clearance" not in planners.check(traj, robot).names  # no scene, no finding


def test_the_bound_between_samples_holds_on_random_cases():
    robot = get_robot("youbot")
    rng = np.random.default_rng(37)
    lower, upper = robot.limits.lower, robot.limits.upper
    for case in range(3):
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        traj = quintic(q0, q1, DURATION)
        middle = robot.tool_pose(traj.sample(np.array([rng.uniform(0.5, 1.5)])).q[0])[:3, 3]
        centre = middle + rng.normal(scale=0.08, size=3)
        scene = Scene((Sphere("post", 0.05, translation(centre)),), margin=0.0)
        finding = planners.check(traj, robot, scene=scene, rate=20.0)["clearance"]
        certified = finding.margin + scene.margin  # the bound over the whole trajectory
        reference, _, _ = _dense(traj, SceneCollision(robot, scene), np.linspace(0, 2, 4001))
        assert reference >= certified - 1e-9, case
        assert certified <= finding.value


def test_reach_bounds_every_shape_point_from_each_joint():
    robot = get_robot("sawyer")
    shapes = SceneCollision(robot, Scene((problems.floor(-0.914),)))
    reach = joint_reach(shapes, [])
    assert np.all(np.diff(reach[1:]) <= 1e-12)  # a joint further out carries less
    assert reach[1] > 1.0  # the whole arm and the 0.3 m cue hang from joint 1


def test_a_carried_object_moves_with_its_frame():
    robot = get_robot("youbot")
    traj = quintic(Q_A, Q_B, DURATION)
    ahead = np.eye(4)
    ahead[2, 3] = 0.15  # 15 cm along the tool axis: far from every link
    start = robot.tool_pose(Q_A) @ ahead
    passing = robot.tool_pose(traj.sample(np.array([1.0])).q[0]) @ ahead
    held = Sphere("held", 0.02, start)
    obstacle = Sphere("obstacle", 0.01, translation(passing[:3, 3]))
    carried = Scene((held, obstacle), (Attachment("held", "tcp", 0.0, DURATION),))
    finding = planners.check(traj, robot, scene=carried)["clearance"]
    assert not finding.ok and finding.detail.startswith("held to obstacle")
    assert finding.time == pytest.approx(1.0, abs=2e-3)
    left = Scene((held, obstacle), (Attachment("held", "tcp", 0.0, 0.5),))
    assert planners.check(traj, robot, scene=left)["clearance"].ok  # let go before


def test_a_missing_attachment_phase_fails_the_finding():
    robot = get_robot("youbot")
    traj = quintic(Q_A, Q_B, DURATION)
    scene = Scene((Sphere("held", 0.02),), (Attachment("held", "tcp", "grasp_0", "release_0"),))
    finding = planners.check(traj, robot, scene=scene)["clearance"]
    assert not finding.ok and "missing" in finding.detail


def test_the_two_block_plan_drags_a_finger_through_the_block_it_put_down():
    task = problems.youbot_two_blocks()
    scene = problems.pick_and_place_scene(task)
    task = dataclasses.replace(task, scene=scene)
    traj = planners.PickAndPlacePlanner(planners.Quintic()).plan(task)
    finding = planners.check(traj, task, rate=100.0)["clearance"]
    # The joint move back to the interim pose after the first release (phase interim_1)
    # sweeps the left finger 1.8 mm into block 0 on the pile.
    interim = next(p for p in traj.phases if p.name == "interim_1")
    assert not finding.ok and finding.detail.startswith("tool/finger_left to block_0")
    assert interim.t_start < finding.time < interim.t_end
    assert finding.value == pytest.approx(-0.0018, abs=3e-4)
    # With that way out allowed too, what is left is the fingers over the work surface.
    out = tuple(
        dataclasses.replace(p, phases=(*p.phases, f"interim_{k + 1}")) if p.phases else p
        for k, p in enumerate(scene.allowed)
    )
    lenient = dataclasses.replace(task, scene=dataclasses.replace(scene, allowed=out))
    finding = planners.check(traj, lenient, rate=100.0)["clearance"]
    assert finding.ok and finding.value == pytest.approx(0.0065, abs=5e-4)


def test_a_scene_whose_pairs_may_all_touch_passes():
    robot = get_robot("youbot")
    scene = Scene((Sphere("post", 0.5),), allowed=(("*", "*"),))
    finding = planners.check(quintic(Q_A, Q_B, DURATION), robot, scene=scene)["clearance"]
    assert finding.ok and finding.detail == "no pair to check"


def test_the_pair_is_read_back_from_a_finding_and_other_findings_are_refused():
    robot = get_robot("sawyer")
    start = robot.home + 0.3
    crate = np.eye(4)
    crate[:3, 3] = robot.tool_pose(start)[:3, 3]
    scene = Scene(objects=(problems.Box("crate", [0.05, 0.05, 0.05], crate),))
    traj = planners.Quintic().plan(problems.PointToPoint(robot, start, robot.home))
    finding = planners.check(traj, robot, scene=scene)["clearance"]
    first, second = clearance_pair(finding)
    assert second == "crate" and first.startswith("tool/") and first in finding.detail
    with pytest.raises(InvalidInputError, match="not a clearance finding"):
        clearance_pair(dataclasses.replace(finding, detail="no pair to check"))
    with pytest.raises(InvalidInputError, match="not a clearance finding"):
        clearance_pair(planners.check(traj, robot)["velocity"])
