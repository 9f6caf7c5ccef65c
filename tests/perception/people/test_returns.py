"""A scan's returns for the person tracker (``perception.people.returns``): the one compiled
pass gives what its three steps give apart, the lidar's returns placed in odom, those the
robot's outline (grown by the margin) holds dropped, the rest carried into the map."""
from __future__ import annotations

import math

import numpy as np

from hw.robot_outline import Capsules, Outline
from nav.frames import transform_points
from hw.odometry import Pose2D
from perception.people.returns import odom_points, returns

ARM = Capsules(np.array([[[0.05, 0.0], [0.2, 0.3]], [[0.2, 0.3], [0.1, 0.45]]]), 0.03)


def test_one_pass_drops_what_the_outline_holds_and_carries_the_rest_into_the_map_wherever_the_robot_stands():
    rng = np.random.default_rng(3)
    body, dropped = Outline(0.165, 0.13, ARM), 0
    for yaw in np.linspace(-math.pi, math.pi, 9):
        robot = (1.0, 2.5, float(yaw))
        lidar = (robot[0] + 0.1 * math.cos(yaw), robot[1] + 0.1 * math.sin(yaw), float(yaw))
        angles = np.sort(rng.uniform(-math.pi, math.pi, 1000))
        ranges = rng.uniform(0.02, 0.8, 1000)
        ranges[rng.random(1000) < 0.1] = np.inf  # no return
        m2o = Pose2D(0.3, -0.2, 0.4 * float(yaw))
        odom, in_map = returns(angles, ranges, lidar, robot, body, 0.05, (m2o.x, m2o.y, m2o.yaw))

        every = odom_points(angles, ranges, lidar)
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = every[:, 0] - robot[0], every[:, 1] - robot[1]
        keep = ~body.inside(c * dx + s * dy, c * dy - s * dx, 0.05)
        np.testing.assert_allclose(odom, every[keep], atol=1e-12)  # scan order kept
        np.testing.assert_allclose(in_map, transform_points(m2o, every[keep]), atol=1e-12)
        dropped += int((~keep).sum())
    assert dropped > 1500  # the arm and chassis held many of them
