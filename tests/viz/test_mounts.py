import numpy as np
from conftest import get_robot

from optraj.viz.mounts import FLOOR_THICKNESS, MOUNTS, mount_of, mount_shapes


def test_sawyer_stands_on_its_pedestal_above_the_floor():
    robot = get_robot("sawyer")
    floor, pedestal = mount_shapes(robot, np.zeros(3), MOUNTS["sawyer"].floor)
    top = floor.pose[2, 3] + FLOOR_THICKNESS / 2
    np.testing.assert_allclose(top, -0.914)
    length = pedestal.size[1]
    ends = sorted(pedestal.pose[2, 3] + s * length / 2 for s in (-1.0, 1.0))
    np.testing.assert_allclose(ends, [-0.914, 0.0], atol=1e-12)


def test_a_lower_floor_lengthens_the_pedestal_and_unknown_robots_stand_at_zero():
    robot = get_robot("youbot")
    _, pedestal = mount_shapes(robot, np.zeros(3), -0.2)
    np.testing.assert_allclose(pedestal.size[1], 0.2)
    assert mount_of(get_robot("paddle4")).floor < -0.275  # below the lowest paddle
