"""Tests of planners.ocp.clearance: the spheres, the setting, and seeded pool shots kept clear.

The seeded shots are judged at 1 kHz with Pinocchio's forward kinematics (the cue runs from
the flange ``right_hand`` to the tip ``cue_tip``), not with the planner's rows or spheres.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from ocp_support import reachable_shots, table_shots

from optraj import planners, problems, robots
from optraj.errors import InfeasibleError, InvalidInputError, SolverError
from optraj.planners import check
from optraj.planners.ocp.clearance import (
    TIP_RADIUS,
    WRIST_LINKS,
    Clearance,
    ball_offset,
    checked_clearance,
    pool_spheres,
    sphere_centres,
    sphere_floors,
)
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.problems import AllowedPair, Scene
from optraj.robots.collision import collision_geometry
from optraj.robots.loading import SAWYER_CUE_LENGTH, SAWYER_CUE_RADIUS

MARGIN = 0.01  # [m], issue 37


@pytest.mark.parametrize("field", ["margin", "ball_gap", "node_extra"])
@pytest.mark.parametrize("value", [-0.01, np.nan, 2.0])
def test_a_clearance_out_of_range_is_refused(field, value):
    with pytest.raises(InvalidInputError, match=field):
        Clearance(**{field: value})


def test_only_a_clearance_or_none_is_a_setting():
    assert checked_clearance(None) is None
    with pytest.raises(InvalidInputError, match="clearance must be"):
        checked_clearance(0.01)
    with pytest.raises(InvalidInputError, match="clearance must be"):
        OptimalControl(clearance=True)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="wrist"):
        Clearance(wrist=1)  # type: ignore[arg-type]


def test_the_spheres_sit_on_the_cue_and_on_the_ends_of_the_wrist_capsules():
    sawyer = robots.load("sawyer")
    spheres = pool_spheres(sawyer, wrist=True)
    names = [s.name for s in spheres]
    assert names[-3:] == ["cue butt", "cue middle", "cue tip"]
    assert names[:3] == ["link_5 end 0", "link_5 middle", "link_5 end 1"]
    q = np.random.default_rng(3).uniform(sawyer.limits.lower, sawyer.limits.upper)
    centres = sphere_centres(sawyer, spheres, q)[0]
    model, data = sawyer.model, sawyer.model.createData()
    pin.framesForwardKinematics(model, data, q)
    # The wrist's spheres: on the capsules the checker measures, placed by Pinocchio.
    geometry = collision_geometry(sawyer)
    placed = pin.GeometryData(geometry)
    pin.updateGeometryPlacements(model, data, geometry, placed, q)
    for name in WRIST_LINKS:
        item = geometry.geometryObjects[geometry.getGeometryId(name)]
        pose = placed.oMg[geometry.getGeometryId(name)]
        half = item.geometry.halfLength
        ends = [pose.act(np.array([0.0, 0.0, z])) for z in (-half, half)]
        mine = [i for i, n in enumerate(names) if n.startswith(f"{name} end")]
        np.testing.assert_allclose(centres[mine], ends, atol=1e-12)
        assert all(spheres[i].radius == item.geometry.radius for i in mine)
    flange = data.oMf[model.getFrameId("right_hand")].translation
    tip = data.oMf[model.getFrameId("cue_tip")]
    np.testing.assert_allclose(centres[-3], flange, atol=1e-12)
    np.testing.assert_allclose(centres[-2], 0.5 * (flange + tip.translation), atol=1e-12)
    np.testing.assert_allclose(
        centres[-1], tip.translation - TIP_RADIUS * tip.rotation[:, 2], atol=1e-12
    )
    assert np.linalg.norm(flange - tip.translation) == pytest.approx(SAWYER_CUE_LENGTH, abs=1e-12)
    assert spheres[-3].radius == SAWYER_CUE_RADIUS
    assert pool_spheres(sawyer, wrist=False) == spheres[-3:]


def test_a_sphere_that_starts_below_its_floor_is_held_where_it_starts():
    shot = problems.sawyer_pool_shot(1.0, ball=(0.75, 0.15, 0.0))  # cloth above the home tip
    spheres = pool_spheres(shot.robot, wrist=False)
    clearance = Clearance()
    floors = sphere_floors(shot, spheres, clearance)
    start = sphere_centres(shot.robot, spheres, shot.q_start)[0, :, 2]
    cloth = shot.ball[2] - shot.ball_radius
    assert start[2] < cloth  # the tip starts in the table
    assert floors[2] == start[2]
    np.testing.assert_allclose(floors[:2], cloth + SAWYER_CUE_RADIUS + 0.015, atol=1e-12)
    short = problems.PoolStrike(shot.robot, shot.ball, shot.direction, 1.0, run_up=0.01)
    assert ball_offset(short, spheres[2], clearance) == pytest.approx(
        short.ball_radius + TIP_RADIUS + 0.005
    )


def _clearances(shot: problems.PoolStrike, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Heights of the cue's butt, middle and tip spheres above the cloth [m], (m, 3), and the
    tip sphere's distance from the ball's surface [m], (m,); Pinocchio's kinematics."""
    model, data = shot.robot.model, shot.robot.model.createData()
    flange_id, tip_id = model.getFrameId("right_hand"), model.getFrameId("cue_tip")
    cloth = shot.ball[2] - shot.ball_radius
    heights, gaps = [], []
    for qk in q:
        pin.framesForwardKinematics(model, data, qk)
        butt = data.oMf[flange_id].translation
        tip = data.oMf[tip_id]
        centre = tip.translation - TIP_RADIUS * tip.rotation[:, 2]
        middle = 0.5 * (butt + tip.translation)
        heights.append(
            [
                butt[2] - SAWYER_CUE_RADIUS - cloth,
                middle[2] - SAWYER_CUE_RADIUS - cloth,
                centre[2] - TIP_RADIUS - cloth,
            ]
        )
        gaps.append(np.linalg.norm(centre - shot.ball) - shot.ball_radius - TIP_RADIUS)
    return np.array(heights), np.array(gaps)


def _assert_clear(shot: problems.PoolStrike, planner: OptimalControl) -> None:
    traj = planner.plan(shot)
    assert check(traj, shot).ok
    t = np.append(np.arange(0.0, traj.duration, 1e-3), traj.duration)
    heights, gaps = _clearances(shot, traj.sample(t).q)
    window = traj.phase("strike")
    heights[(t >= window.t_start) & (t <= window.t_end), 2] = np.inf  # the tip strikes there
    # A sphere that starts in the table (the home pose puts the tip below the cloth of some
    # shots) cannot be lifted at once: it keeps no lower than it starts, within 1 mm.
    wanted = np.minimum(MARGIN, heights[0] - 1e-3)
    assert np.all(heights.min(axis=0) >= wanted), (heights.min(axis=0), heights[0])
    assert gaps[t < window.t_start].min() >= 0.0


def test_the_default_pool_shot_keeps_the_cue_clear():
    _assert_clear(problems.sawyer_pool_shot(1.0), OptimalControl("time"))


@pytest.mark.slow
@pytest.mark.parametrize(
    "shot", reachable_shots(20), ids=lambda s: f"{s.ball[0]:.3f},{s.ball[1]:.3f}"
)
def test_seeded_pool_shots_keep_the_cue_above_the_cloth_and_off_the_ball(shot, planner_time):
    _assert_clear(shot, planner_time)


@pytest.fixture(scope="module")
def planner_time() -> OptimalControl:
    """One planner for every shot: its compiled NLP is reused."""
    return OptimalControl("time")


# Issue 37: 100 seeded random shots over a table (problems.sawyer_pool_shot(with_table=True): the
# cue raised 4 deg, the arm starting cue up) keep the arm and the cue at least 1 cm above the
# cloth; each is planned or refused with a typed error, every plan judged by the checker's
# clearance against the cloth alone (the arm's own pairs are another check's business).
#: Shots drawn, and the least that must be planned (measured: 65 of 100 planned; the rest
#: refused with a typed error: no contact configuration clear of the table fast enough for
#: 1 m/s, or IPOPT finding the raised-cue window infeasible).
SHOTS = 100
PLANNED = 60
CLOTH_CLEARANCE = 0.01


def _cloth(shot: problems.PoolStrike) -> Scene:
    """The cloth alone, every robot shape kept 1 cm from it (the robot's own pairs allowed)."""
    own = (("link_*", "link_*"), ("link_*", "tool/*"), ("tool/*", "tool/*"))
    return Scene(
        (shot.scene.object("cloth"),),
        allowed=tuple(AllowedPair(a, b) for a, b in own),
        margin=CLOTH_CLEARANCE,
    )


@pytest.mark.slow
def test_seeded_shots_over_a_table_keep_the_arm_and_cue_a_centimetre_above_the_cloth():
    # The shoulder's rows are off here (they cost about 7 times the solve time);
    # tests/planners/ocp/task_rows/test_clearance.py keeps them on.
    planner = planners.OptimalControl(clearance=Clearance(shoulder=False))
    planned, refused = 0, []
    for shot in table_shots(SHOTS):
        try:
            traj = planner.plan(shot)
        except (InfeasibleError, SolverError) as error:
            refused.append(type(error).__name__)
            continue
        finding = planners.check(traj, shot.robot, scene=_cloth(shot))["clearance"]
        assert finding.ok, (shot.ball, shot.direction, finding.detail)
        assert finding.value >= CLOTH_CLEARANCE
        planned += 1
    print(f"planned {planned} of {SHOTS}; refused: {sorted(refused)}")
    assert planned >= PLANNED, refused
