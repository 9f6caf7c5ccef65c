import math

import pytest

from hw.config import BaseConfig
from hw.interfaces import Twist
from hw.mecanum import Mecanum
from hw.odometry import Pose2D, WheelOdometry


@pytest.fixture
def odom():
    return WheelOdometry(Mecanum.from_config(BaseConfig()))


def test_known_arc_quarter_circle(odom):
    # 0.2 m/s forward at 0.4 rad/s: radius 0.5 m; a quarter turn takes pi/2/0.4 s.
    v, w = 0.2, 0.4
    wheels = odom.mecanum.inverse(Twist(v, 0, w))
    steps = 100
    dt = (math.pi / 2 / w) / steps
    for _ in range(steps):
        odom.update(wheels, dt)
    p = odom.pose
    assert p.x == pytest.approx(0.5, abs=1e-9)
    assert p.y == pytest.approx(0.5, abs=1e-9)
    assert p.yaw == pytest.approx(math.pi / 2, abs=1e-9)
    assert odom.distance == pytest.approx(0.5 * math.pi / 2, abs=1e-9)
    assert odom.twist.vx == pytest.approx(v) and odom.twist.wz == pytest.approx(w)


def test_arc_is_exact_even_with_one_big_step(odom):
    odom.integrate(Twist(0.2, 0, 0.4), math.pi / 2 / 0.4)
    assert (odom.pose.x, odom.pose.y) == pytest.approx((0.5, 0.5), abs=1e-12)


def test_strafe_in_rotated_frame(odom):
    odom.reset(Pose2D(1.0, 2.0, math.pi / 2))
    odom.integrate(Twist(0, 0.3, 0), 2.0)  # strafe left while facing +y: moves -x
    assert (odom.pose.x, odom.pose.y, odom.pose.yaw) == pytest.approx((0.4, 2.0, math.pi / 2))
    assert odom.distance == pytest.approx(0.6)


def test_spin_in_place_wraps_and_adds_no_distance(odom):
    for _ in range(30):
        odom.integrate(Twist(0, 0, 1.0), 0.25)  # 7.5 rad
    assert odom.pose.yaw == pytest.approx(math.remainder(7.5, 2 * math.pi))
    assert -math.pi < odom.pose.yaw <= math.pi
    assert odom.distance == 0.0 and (odom.pose.x, odom.pose.y) == (0.0, 0.0)


def test_reset(odom):
    odom.integrate(Twist(1, 0, 0), 1.0)
    odom.reset()
    assert odom.pose == Pose2D() and odom.distance == 0.0


def test_pose_is_frozen():
    with pytest.raises(AttributeError):
        Pose2D().x = 1.0  # type: ignore[misc]
