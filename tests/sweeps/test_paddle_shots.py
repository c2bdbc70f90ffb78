import numpy as np
import pytest
from sweeps_support import PADDLE, velocity_ratio

from optraj import planners, problems, robots
from optraj.errors import InvalidInputError
from optraj.planners import registry
from optraj.sweeps import PaddleShotSet, ShotJob
from optraj.sweeps.paddle_shots import PADDLE_KIND


def test_grid_order_ids_and_count():
    shots = PaddleShotSet(
        x=(0.6, 0.8), y=(0.0, 0.2), z=(0.1, 0.3), grid=(2, 2, 3), headings=(0.0, 10.0)
    )
    found = shots.shots()
    assert len(shots) == len(found) == 24
    assert [s.ball for s in found[:4:2]] == [(0.6, 0.0, 0.1), (0.6, 0.0, 0.2)]
    assert [s.heading for s in found[:2]] == [0.0, 10.0]
    assert {s.kind for s in found} == {"paddle-strike"} and {s.robot for s in found} == {"paddle4"}
    assert found[0].shot_id == "paddle4:paddle-strike:x=0.6000:y=0.0000:z=0.1000:h=0.000:v=0.5000"
    assert len({s.shot_id for s in found}) == 24 and shots.shots() == found
    assert shots[-1] == found[-1] and shots[7] == found[7]


def test_random_set_is_seeded_and_in_range():
    settings = {"x": (0.6, 0.9), "z": (0.0, 0.5), "headings": (-30.0, 30.0), "samples": 20}
    shots = PaddleShotSet(**settings, seed=3)
    assert shots.shots() == PaddleShotSet(**settings, seed=3).shots()
    assert shots.shots() != PaddleShotSet(**settings, seed=4).shots()
    for shot in shots:
        assert 0.6 <= shot.ball[0] <= 0.9 and -0.3 <= shot.ball[1] <= 0.3
        assert 0.0 <= shot.ball[2] <= 0.5 and -30.0 <= shot.heading <= 30.0


def test_problem_is_the_paddle_strike_at_the_contact_angle():
    shot = PaddleShotSet(x=(0.8, 0.8), y=(0.2, 0.2), grid=(1, 1, 1), headings=(15.0,))[0]
    mine = shot.problem()
    assert isinstance(mine, problems.PaddleStrike) and mine.speed == 0.5
    robot = robots.load("paddle4")
    q = robots.paddle4_ik(robot, (0.8, 0.2, 0.3), np.radians(15.0))
    np.testing.assert_allclose(mine.q_contact, q, atol=1e-12)
    np.testing.assert_allclose(mine.normal, [np.cos(np.radians(15)), np.sin(np.radians(15)), 0])


@pytest.mark.parametrize("name", ["ruckig", "optimal-control"])
def test_paddle_shots_plan_within_the_limits(name):
    job = ShotJob(registry.make_planner(PADDLE_KIND, name), name)
    for shot in PADDLE:
        row = job.row(shot)
        assert row["status"] == "planned" and row["kind"] == "paddle-strike", row
        problem = shot.problem()
        plan = registry.make_planner(PADDLE_KIND, name).plan(problem)
        assert row["check_ok"] is planners.check(plan, problem).ok is True
        # With the normal held still at contact (ruckig), the paddle's joint velocity there is
        # unique: its largest share of the velocity limits is the speed over the row's fastest
        # speed. The OCP lets the paddle turn a little at contact, which needs a few % less.
        contact = plan.phase("approach").t_end
        ratio = velocity_ratio(plan, problem.limits, contact, contact, samples=1)
        share = ratio / (shot.speed / row["max_speed"])
        assert abs(share - 1.0) < 1e-3 if name == "ruckig" else 0.9 < share < 1.0 + 1e-3
        assert (
            row["binding_quantity"] == "velocity" and row["binding_joint"] in problem.limits.names
        )


def test_a_paddle_strike_past_its_fastest_speed_is_refused():
    job = ShotJob(registry.make_planner(PADDLE_KIND, "ruckig"), "ruckig")
    slow = PaddleShotSet(x=(0.8, 0.8), y=(0.1, 0.1), grid=(1, 1, 1), speeds=(0.5,))[0]
    fastest = job.row(slow)["max_speed"]
    fast = PaddleShotSet(x=(0.8, 0.8), y=(0.1, 0.1), grid=(1, 1, 1), speeds=(1.02 * fastest,))
    row = job.row(fast[0])
    assert row["status"] == "refused" and row["binding_quantity"] == "velocity"


@pytest.mark.parametrize(
    ("settings", "words"),
    [
        ({"x": (0.2, 0.9)}, "x must be >= 0.3 m, got 0.2 m"),
        ({"y": (0.0, 0.9)}, "y must be <= 0.8 m, got 0.9 m"),
        ({"z": (0.4, 0.3)}, "z must have first <= last"),
        ({"z": (0.3,)}, "z must be a (first, last) pair"),
        ({"speeds": (-0.1,)}, "speeds must be >= 0 m/s, got -0.1 m/s"),
        ({"speeds": (400.0,)}, "speeds must be <= 343 m/s, got 400 m/s"),
        ({"headings": (-400.0,)}, "headings must be >= -360 deg, got -400 deg"),
        ({"grid": (2, 2)}, "grid must be a triple"),
        ({"grid": (2, 0, 1)}, "grid must be an integer >= 1, got 0"),
        ({"grid": (1000, 1000, 2), "z": (0.2, 0.4)}, "at most 1000000 shots, got 2000000"),
        ({"samples": 0}, "samples must be an integer >= 1, got 0"),
        ({"seed": -2}, "seed must be an integer >= 0, got -2"),
    ],
)
def test_bad_input_names_value_and_limit(settings, words):
    with pytest.raises(InvalidInputError) as info:
        PaddleShotSet(**settings)
    assert words in str(info.value)
