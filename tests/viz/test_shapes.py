import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.viz.shapes import along, box, polyline, segment, sphere

RED = (1.0, 0.0, 0.0, 1.0)


def test_along_is_a_rotation_onto_the_axis():
    rng = np.random.default_rng(3)
    for axis in [*rng.normal(size=(20, 3)), (1.0, 0.0, 0.0), (0.0, 0.0, -2.0)]:
        R = along(axis)
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
        np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
        np.testing.assert_allclose(R[:, 2], np.asarray(axis) / np.linalg.norm(axis), atol=1e-12)


def test_along_refuses_a_zero_axis():
    with pytest.raises(InvalidInputError, match="no direction"):
        along((0.0, 0.0, 0.0))


def test_segment_runs_from_start_to_end():
    a, b = np.array([0.1, -0.2, 0.3]), np.array([0.5, 0.4, -0.1])
    shape = segment("s", a, b, 0.01, RED)
    assert shape is not None and shape.kind == "cylinder"
    radius, length = shape.size
    assert radius == 0.01
    np.testing.assert_allclose(length, np.linalg.norm(b - a))
    ends = [shape.pose @ np.array([0.0, 0.0, s * length / 2, 1.0]) for s in (-1.0, 1.0)]
    np.testing.assert_allclose(ends[0][:3], a, atol=1e-12)
    np.testing.assert_allclose(ends[1][:3], b, atol=1e-12)
    assert segment("s", a, a, 0.01, RED) is None


def test_box_and_sphere_sit_where_asked():
    cube = box("b", (1.0, 2.0, 3.0), (0.1, 0.2, 0.3), RED)
    assert cube.size == (0.1, 0.2, 0.3)
    np.testing.assert_allclose(cube.pose[:3, 3], (1.0, 2.0, 3.0))
    ball = sphere("s", (0.0, 0.0, 1.0), 0.5, RED)
    assert ball.size == (0.5,) and ball.motion is None


def test_polyline_keeps_the_ends_and_at_most_the_given_count():
    t = np.linspace(0.0, 1.0, 500)
    points = np.column_stack([t, np.sin(3 * t), np.zeros_like(t)])
    shapes = polyline("path", points, 0.002, RED, most=40)
    assert 10 <= len(shapes) <= 39
    assert [s.name for s in shapes[:2]] == ["path/0", "path/1"]
    first, last = shapes[0], shapes[-1]
    start = first.pose @ np.array([0.0, 0.0, -first.size[1] / 2, 1.0])
    end = last.pose @ np.array([0.0, 0.0, last.size[1] / 2, 1.0])
    np.testing.assert_allclose(start[:3], points[0], atol=1e-12)
    np.testing.assert_allclose(end[:3], points[-1], atol=1e-12)


def test_polyline_of_one_point_or_a_still_ball_is_empty():
    assert polyline("p", np.zeros((1, 3)), 0.01, RED) == []
    assert polyline("p", np.zeros((30, 3)), 0.01, RED) == []
