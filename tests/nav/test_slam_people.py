"""SLAM neither registers nor maps the returns on people pressing on the robot
(nav/slam/people_mask.py): a cart that shoves the robot along with its wheels still no longer
holds the pose where the wheels say."""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person
from nav.frames import compose
from nav.slam.config import SlamConfig
from nav.slam.mapper import Mapper
from nav.slam.people_mask import MARGIN, PRESS_FOR, Pressing, on_people
from tests.nav.builders import greenhouse_occupancy, scan_from_occupancy

RES = 0.05
MOUNT = Pose2D(0.115, 0.0, 0.0)
GREENHOUSE = greenhouse_occupancy(floor=(9.0, 5.0), rows=(1.5, 2.5, 3.5), pots_x=(2.0, 3.0, 4.0, 5.0, 6.0, 7.0))
CART_BEHIND, CART_HALF = 0.55, (0.3, 0.6)
"""A cart 0.6 m deep and 1.2 m wide, its centre this far behind the robot's, m (pushed against it)."""


def with_cart(x: float, y: float) -> tuple[np.ndarray, tuple[float, float]]:
    """The greenhouse with a cart against the back of a robot at (x, y) facing +x, and the
    cart's centre."""
    occ = GREENHOUSE.copy()
    h, w = occ.shape
    yy, xx = np.mgrid[0:h, 0:w]
    cx, cy = x - CART_BEHIND, y
    occ[(np.abs((xx + 0.5) * RES - cx) <= CART_HALF[0]) & (np.abs((yy + 0.5) * RES - cy) <= CART_HALF[1])] = 100
    return occ, (cx, cy)


def shoved(tell_people: bool, step: float = 0.03, scans: int = 30) -> float:
    """Where SLAM puts a robot a cart pushes ``step`` m along +x per scan for ``scans`` scans, its
    wheels still (odometry stands at the origin throughout), after ten scans standing: the error
    against the truth, m. ``tell_people``: the cart is a tracked person (odom frame)."""
    start = (1.2, 1.0)
    mapper = Mapper(SlamConfig(), MOUNT, Pose2D(*start, 0.0))
    x, y = start
    for k in range(scans + 10):
        x += step if k >= 10 else 0.0
        occ, (cx, cy) = with_cart(x, y)
        scan = scan_from_occupancy(occ, RES, (x + MOUNT.x, y, 0.0))
        cart = [Person(1, cx - x, cy - y, 0.0, 0.0, math.hypot(*CART_HALF), 1.0)] if tell_people else []
        pose = mapper.process(scan.angles, scan.ranges, Pose2D(), on_people(scan.angles, scan.ranges, MOUNT, cart))
    return math.hypot(pose.x - x, pose.y - y)


def test_a_cart_shoving_the_robot_does_not_hold_slam_where_the_wheels_say():
    """Pushed 0.9 m by a cart against its back, wheels still: the cart's box, matched where it
    stands in the lidar's frame, holds registration back (the error is the motion it missed);
    with the cart's returns left out, the pots and walls carry the pose along."""
    assert shoved(tell_people=False) > 0.08
    assert shoved(tell_people=True) < 0.04


def test_the_returns_on_a_person_are_those_within_their_radius_and_the_margin():
    angles = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    ranges = np.full(360, 3.0)
    ranges[10] = np.inf
    lidar = Pose2D(1.0, 2.0, 0.5)
    person = Person(7, 1.0 + 2.0 * math.cos(0.5), 2.0 + 2.0 * math.sin(0.5), 0.0, 0.0, 0.3, 1.0)
    assert on_people(angles, ranges, lidar, []) is None
    ranges_near = ranges.copy()
    ranges_near[(np.abs(angles) < 0.25)] = 2.0  # a body 2 m ahead of the lidar, dead ahead in its frame
    hit = on_people(angles, ranges_near, lidar, [person])
    x = lidar.x + ranges_near * np.cos(angles + lidar.yaw)
    y = lidar.y + ranges_near * np.sin(angles + lidar.yaw)
    want = np.hypot(x - person.x, y - person.y) <= person.radius + MARGIN
    assert want.any() and np.array_equal(hit, want)
    assert not hit[10]  # no return: nothing to leave out
    assert on_people(angles, ranges, lidar, [person]) is None  # at 3 m, behind the person: not theirs


def test_slam_judges_trust_on_every_return_before_it_leaves_peoples_out():
    """A person close by covering most of the view is something seen, not a blind lidar: the
    scan is still registered (on what is left), not coasted over on the wheels."""
    mapper = Mapper(SlamConfig(), MOUNT, Pose2D(4.5, 1.0, 0.0))
    for _ in range(3):
        scan = scan_from_occupancy(GREENHOUSE, RES, (4.5 + MOUNT.x, 1.0, 0.0))
        everyone = np.isfinite(scan.ranges) & (np.abs(scan.angles) < 2.0)  # two thirds of the view
        mapper.process(scan.angles, scan.ranges, Pose2D(), everyone)
    assert mapper.blind_scans == 0 and mapper.scans == 3


def test_only_people_pressing_on_the_robot_are_left_out_and_only_for_a_while():
    """A cart against the robot is left out of SLAM for ``PRESS_FOR`` s of its press; someone a
    metre off never; a false person standing against the robot is mapped again after that
    (left out for good, the map never explained it away: stop 52's experiments)."""
    t = [0.0]
    cart, far = Person(1, 0.5, 0.0, 0.0, 0.0, 0.4, 1.0), Person(2, 2.0, 0.0, 0.0, 0.0, 0.3, 1.0)
    gaps = {1: 0.0, 2: 1.0}
    pressing = Pressing(lambda: [cart, far], lambda p: gaps[p.id], lambda: t[0])
    assert pressing() == [cart]
    t[0] = PRESS_FOR - 0.1
    assert pressing() == [cart]
    t[0] = PRESS_FOR + 0.1
    assert pressing() == []  # pressing on and on: a thing, to be mapped
    gaps[1] = 1.0
    t[0] += PRESS_FOR + 0.5  # gone a while, then pressing again: a new press
    pressing()
    gaps[1] = 0.05
    assert pressing() == [cart]


def slid_under_a_cart(step: float, turn: float) -> tuple[Mapper, Pose2D, Pose2D]:
    """A robot standing in an aisle, then a cart over its lidar (every return on it, a tracked
    person) while it slides ``step`` m along -y and turns ``turn`` rad a scan for ten scans, its
    wheels still, then the cart gone: the mapper, its pose and the truth after five clear scans."""
    truth = Pose2D(1.5, 2.0, 0.0)
    mapper = Mapper(SlamConfig(), MOUNT, truth)

    def seen(pose: Pose2D):
        lidar = compose(pose, MOUNT)
        return scan_from_occupancy(GREENHOUSE, RES, (lidar.x, lidar.y, lidar.yaw))

    for _ in range(10):
        scan = seen(truth)
        mapper.process(scan.angles, scan.ranges, Pose2D())
    for _ in range(10):
        truth = Pose2D(truth.x, truth.y - step, truth.yaw + turn)
        angles = seen(truth).angles
        ranges = np.full(len(angles), 0.3)  # the cart's faces all round the lidar
        cart = [Person(1, MOUNT.x, 0.0, 0.0, 0.0, 0.35, 1.0)]
        mapper.process(angles, ranges, Pose2D(), on_people(angles, ranges, MOUNT, cart))
    for _ in range(5):
        scan = seen(truth)
        pose = mapper.process(scan.angles, scan.ranges, Pose2D())
    return mapper, pose, truth


def test_a_robot_slid_under_a_cart_is_found_again_when_the_cart_has_gone():
    """safety.people seed 104 (``nav.slam.relocate``): a cart over the lidar slid the robot 0.64 m
    and turned it 0.19 rad, the wheels felt nothing, and SLAM's pose stayed where the shove began,
    for good. The hidden scans are coasted over, and the first clear one is searched for."""
    mapper, pose, truth = slid_under_a_cart(0.06, 0.02)
    assert mapper.blind_scans == 10 and mapper.odometry.relocations == 1
    assert math.hypot(pose.x - truth.x, pose.y - truth.y) < 0.03 and abs(pose.yaw - truth.yaw) < 0.01, (pose, truth)
    mapper, pose, truth = slid_under_a_cart(0.0, 0.0)  # only leaned on: it stays where it was
    assert mapper.odometry.relocations == 1
    assert math.hypot(pose.x - truth.x, pose.y - truth.y) < 0.01 and abs(pose.yaw - truth.yaw) < 0.005, (pose, truth)
