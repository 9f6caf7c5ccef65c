"""The runtime's people (mission/runtime/people.py) on synthetic scans: nothing is tracked until
the patrol names its pots; then pots and mapped walls are not people and a worker's legs are, in
odom; a wall the first map lacked is taken in once SLAM's map has it (long: structure), while the
worker, written into the live map as they stand, stays a person (small: never taken in); the
rules act on tracks that have walked, from then on, standing or not."""
from __future__ import annotations

import math

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from mission.runtime.people import People, first_and_structure
from nav.occupancy import OccupancyMap
from perception.people.config import PeopleConfig
from tests.perception.people.synthetic import greenhouse, mapped

ODOM = Pose2D(1.0, 2.5, 0.0)
MOUNT = Pose2D(0.115, 0.0, 0.0)
WORKER = (3.0, 2.5)


def scene():
    """The greenhouse, two rows of pots and a column of them before the east wall, which they
    break into short arcs as the robot sees it."""
    s = greenhouse()
    pots = s.pot_row(2.0, 1.5, 4) + s.pot_row(2.0, 3.5, 4)
    for y in np.arange(0.4, 4.7, 0.4):
        pots += s.pot_row(7.6, float(y), 1)
    return s, pots


def lidar_scan(points: np.ndarray, stamp: float) -> LidarScan:
    """Scene-frame returns (scan order) as the lidar on the robot at ``ODOM`` measured them."""
    lx, ly = ODOM.x + MOUNT.x, ODOM.y + MOUNT.y
    d = points - [lx, ly]
    return LidarScan(stamp, np.arctan2(d[:, 1], d[:, 0]).astype(np.float32),
                     np.hypot(d[:, 0], d[:, 1]).astype(np.float32))


def with_cells(m: OccupancyMap, x: float, y: float, r: float) -> OccupancyMap:
    occ = m.occupancy.copy()
    g = m.geometry
    gy, gx = np.mgrid[0:g.height, 0:g.width]
    cx, cy = g.centre_of(gx, gy)
    occ[np.hypot(cx - x, cy - y) <= r] = 100
    return OccupancyMap(occ, m.resolution, m.origin_x, m.origin_y)


class Rig:
    def __init__(self, first: OccupancyMap):
        s, self.pots = scene()
        s.legs(*WORKER, heading=math.pi / 2)
        self.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        self.map = first
        self.t = 0.0
        self.people = People(PeopleConfig(), lambda: lidar_scan(self.points, self.t), lambda: ODOM, MOUNT,
                             Pose2D, lambda: self.map)

    def ticks(self, n: int):
        for _ in range(n):
            self.t = round(self.t + 0.1, 6)
            self.people.tick(self.t)
        return self.people.current()


def test_no_one_is_tracked_until_the_patrol_names_its_pots_then_only_the_worker():
    walls, pots = scene()
    rig = Rig(mapped(walls))
    assert rig.ticks(5) == ()
    rig.people.watch(pots, 0.10)
    people = rig.ticks(5)
    assert len(people) == 1
    p = people[0]
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15 and p.confidence >= 0.5


def test_a_wall_the_first_map_lacked_is_taken_in_from_slam_but_a_standing_worker_never_is():
    walls, pots = scene()
    east = walls.walls.pop(1)  # the first map never saw the east wall behind its pots
    first = mapped(walls)
    walls.walls.insert(1, east)
    rig = Rig(first)
    rig.people.watch(pots, 0.10)
    on_wall = rig.points[:, 0] > 7.9
    legs = np.hypot(rig.points[:, 0] - WORKER[0], rig.points[:, 1] - WORKER[1]) < 0.3
    assert on_wall.sum() > 10 and legs.sum() > 5
    rig.ticks(1)
    assert not rig.people.scene.explained(rig.points)[on_wall].any()
    rig.map = with_cells(mapped(walls), *WORKER, 0.2)  # SLAM's map now: the east wall, and the worker
    after = rig.ticks(5)
    explained = rig.people.scene.explained(rig.points)
    assert explained[on_wall].all() and not explained[legs].any()
    assert any(math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15 for p in after)


def test_structure_is_what_is_longer_than_a_person_plus_the_first_map():
    walls, _ = scene()
    first = OccupancyMap(np.zeros_like(mapped(walls).occupancy), 0.05, -0.1, -0.1)
    first = with_cells(first, 6.0, 1.0, 0.1)  # something small the first map held
    live = with_cells(mapped(walls), *WORKER, 0.2)
    taken = first_and_structure(first, live, PeopleConfig().max_extent)
    g = live.geometry
    def at(x, y):
        ix, iy = g.cell_of(x, y)
        return bool(taken[iy, ix])
    assert at(4.0, 0.0) and at(0.0, 2.5)  # walls
    assert not at(*WORKER)  # the worker's blob
    assert at(6.0, 1.0)  # the first map's


def test_the_rules_act_on_a_track_once_it_has_walked_and_on_while_it_stands():
    walls, pots = scene()
    rig = Rig(mapped(walls))
    rig.people.watch(pots, 0.10)
    rig.ticks(15)
    assert rig.people.current() and rig.people.confident() == ()  # standing there: not shown a person yet
    for k in range(25):  # walks 1 m east at 0.4 m/s
        s, _ = scene()
        s.legs(WORKER[0] + 0.04 * (k + 1), WORKER[1], heading=math.pi / 2)
        rig.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        rig.ticks(1)
    assert len(rig.people.confident()) == 1
    rig.ticks(20)  # stands again where it stopped
    (p,) = rig.people.confident()
    assert abs(p.x - (WORKER[0] + 1.0)) < 0.15 and math.hypot(p.vx, p.vy) == 0.0
