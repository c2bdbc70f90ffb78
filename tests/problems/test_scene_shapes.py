"""Scene shapes: validated sizes and poses, and the coal shapes they stand for."""

from __future__ import annotations

import coal
import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.problems.scene_shapes import Box, Cylinder, Plane, Sphere, translation


def test_shapes_give_coal_shapes_of_their_sizes():
    box = Box("b", (0.1, 0.2, 0.3), translation((1, 2, 3)))
    assert isinstance(box.shape(), coal.Box)
    np.testing.assert_allclose(box.shape().halfSide, [0.1, 0.2, 0.3])
    np.testing.assert_allclose(box.pose[:3, 3], [1, 2, 3])
    assert Sphere("s", 0.05).shape().radius == 0.05
    cylinder = Cylinder("c", 0.02, 0.1).shape()
    assert (cylinder.radius, cylinder.halfLength) == (0.02, 0.1)
    np.testing.assert_allclose(Sphere("s", 0.05).pose, np.eye(4))


def test_a_plane_has_its_normal_as_z_axis_and_its_point_as_origin():
    plane = Plane("p", point=(0, 0, -0.5), normal=(0, 3, 4))
    np.testing.assert_allclose(plane.normal, [0, 0.6, 0.8])
    np.testing.assert_allclose(plane.pose[:3, 2], [0, 0.6, 0.8])
    np.testing.assert_allclose(plane.pose[:3, 3], [0, 0, -0.5])
    R = plane.pose[:3, :3]
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Box("b", (0.1, -0.2, 0.3)), "half_extents"),
        (lambda: Box("b", (0.1, 0.2)), "half_extents"),
        (lambda: Sphere("s", 0.0), "radius"),
        (lambda: Cylinder("c", 0.1, float("nan")), "half_length"),
        (lambda: Plane("p", (0, 0, 0), (0, 0, 0)), "normal"),
        (lambda: Sphere("", 0.1), "name"),
        (lambda: Sphere("s", 0.1, np.diag([2.0, 1.0, 1.0, 1.0])), "pose"),
    ],
)
def test_bad_shapes_are_refused_naming_the_field(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build()
