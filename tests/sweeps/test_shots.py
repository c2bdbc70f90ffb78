import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.sweeps import PaddleShotSet, Shot, ShotSet
from optraj.sweeps.shots import make_shot


def test_grid_order_ids_and_count():
    shots = ShotSet(x=(0.7, 0.8), y=(0.0, 0.2), grid=(2, 3), headings=(0.0, 10.0), speeds=(0.5,))
    found = shots.shots()
    assert len(shots) == len(found) == 12
    assert [s.ball[:2] for s in found[:4]] == [(0.7, 0.0), (0.7, 0.0), (0.7, 0.1), (0.7, 0.1)]
    assert [s.heading for s in found[:2]] == [0.0, 10.0]
    assert found[0].shot_id == "sawyer:x=0.7000:y=0.0000:z=-0.0500:h=0.000:v=0.5000"
    assert len({s.shot_id for s in found}) == 12
    assert shots.shots() == found  # a fixed order, the same ids every time
    assert shots[5] == found[5] and shots[-1] == found[-1]
    with pytest.raises(IndexError, match="outside a set of 12 shots"):
        shots[12]


def test_random_set_is_seeded_and_in_range():
    shots = ShotSet(
        x=(0.7, 0.8), y=(0.0, 0.2), headings=(-20.0, 20.0), speeds=(0.3, 0.6), samples=20, seed=3
    )
    again = ShotSet(
        x=(0.7, 0.8), y=(0.0, 0.2), headings=(-20.0, 20.0), speeds=(0.3, 0.6), samples=20, seed=3
    )
    other = ShotSet(
        x=(0.7, 0.8), y=(0.0, 0.2), headings=(-20.0, 20.0), speeds=(0.3, 0.6), samples=20, seed=4
    )
    assert shots.shots() == again.shots() != other.shots()
    assert len(shots) == 20
    for shot in shots:
        assert 0.7 <= shot.ball[0] <= 0.8 and 0.0 <= shot.ball[1] <= 0.2
        assert -20.0 <= shot.heading <= 20.0 and 0.3 <= shot.speed <= 0.6


def test_problem_is_the_scenario_pool_shot():
    shot = ShotSet(x=(0.75, 0.75), y=(0.15, 0.15), grid=(1, 1), headings=(30.0,), speeds=(0.4,))[0]
    assert isinstance(shot, Shot)
    mine = shot.problem()
    theirs = problems.sawyer_pool_shot(0.4, (0.75, 0.15, -0.05), heading_deg=30.0)
    np.testing.assert_allclose(mine.direction, theirs.direction, atol=1e-15)
    np.testing.assert_allclose(mine.q_contact, theirs.q_contact, atol=1e-12)
    assert mine.speed == theirs.speed


@pytest.mark.parametrize(
    ("settings", "words"),
    [
        ({"x": (0.9, 0.8)}, "x must have first <= last"),
        ({"x": (0.0, 9.0)}, "x must be <= 5 m, got 9 m"),
        ({"y": (0.1,)}, "y must be a (first, last) pair"),
        ({"speeds": (0.0,)}, "speeds must be > 0 m/s, got 0 m/s"),
        ({"speeds": ()}, "speeds must be a non-empty tuple"),
        ({"headings": (400.0,)}, "headings must be <= 360 deg, got 400 deg"),
        ({"grid": (0, 3)}, "grid must be an integer >= 1, got 0"),
        ({"grid": (2000, 3)}, "grid must be an integer <= 1000, got 2000"),
        ({"grid": 3}, "grid must be a pair"),
        ({"samples": 0}, "samples must be an integer >= 1, got 0"),
        ({"z": float("nan")}, "z must be finite"),
        ({"seed": -1}, "seed must be an integer >= 0, got -1"),
        ({"grid": (1000, 1000), "speeds": (0.3, 0.6)}, "at most 1000000 shots, got 2000000"),
    ],
)
def test_bad_input_names_value_and_limit(settings, words):
    with pytest.raises(InvalidInputError) as info:
        ShotSet(**settings)
    assert words in str(info.value)


def test_unknown_robot():
    with pytest.raises(UnknownNameError, match="robot"):
        ShotSet(robot="r2d2")


def test_kind_defaults_to_pool_and_names_paddle_ids():
    shot = ShotSet(grid=(1, 1))[0]
    assert shot.kind == "pool-shot" and shot == Shot(*[getattr(shot, f) for f in FIELDS])
    paddle = make_shot("paddle4", (0.8, 0.1, 0.3), 10.0, 0.5, "paddle-strike")
    assert paddle.shot_id == "paddle4:paddle-strike:x=0.8000:y=0.1000:z=0.3000:h=10.000:v=0.5000"
    assert isinstance(paddle.problem(), problems.PaddleStrike)
    with pytest.raises(UnknownNameError, match="unknown shot kind 'pick-and-place'"):
        Shot("a", "sawyer", (0.7, 0.0, -0.05), 0.0, 0.5, kind="pick-and-place")


FIELDS = ("shot_id", "robot", "ball", "heading", "speed")


def test_a_grid_over_a_single_value_is_refused():
    with pytest.raises(
        InvalidInputError, match=r"grid has 3 positions along y, but y is the single"
    ):
        ShotSet(y=(0.1, 0.1), grid=(2, 3))
    assert len(ShotSet(y=(0.1, 0.1), grid=(2, 1))) == 2
    assert len(ShotSet(y=(0.1, 0.1), grid=(2, 3), samples=4)) == 4  # random: fine
    with pytest.raises(InvalidInputError, match=r"along z, but z is the single value 0.3 m"):
        PaddleShotSet(grid=(2, 1, 2))
