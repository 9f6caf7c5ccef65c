"""The SLAM checkpoint: what a respawned worker goes on from (issue 29, item 4).

In process: the mapper's deltas add up to its state, and a mapper restored from them starts
with the map it had and registers its first scan against it. With a real worker process (off
the simulator, a robot driving down the synthetic greenhouse's aisle): a worker that wedges for
real is replaced by one that goes on from the checkpoint; the operator's map reset still starts
an empty map.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pytest

from hw.odometry import Pose2D
from nav.occupancy import OccupancyMap
from nav.slam.checkpoint import Checkpoint, Delta
from nav.slam.config import SlamConfig
from nav.slam.mapper import Mapper
from nav.slam.supervisor import SlamSupervisor
from tests.nav.builders import RES, greenhouse_occupancy, scan_from_occupancy

OCC = greenhouse_occupancy()
MOUNT = Pose2D(0.115, 0.0, 0.0)
START = Pose2D(1.0, 0.5, 0.0)
"""The robot at the default world's dock, in the aisle between the wall and the first row; the
map frame here is the world's (odometry starts at the dock's pose), so truth is easy to read."""


def scan_at(pose: Pose2D, stamp: float = 0.0):
    lidar = (pose.x + MOUNT.x * math.cos(pose.yaw), pose.y + MOUNT.x * math.sin(pose.yaw), pose.yaw)
    s = scan_from_occupancy(OCC, RES, lidar)
    return type(s)(stamp, s.angles, s.ranges)


def along_aisle(k: int) -> Pose2D:
    """The robot's pose after ``k`` scans driving down the aisle at 0.5 m/s (10 Hz scans)."""
    return Pose2D(START.x + 0.05 * k, START.y, 0.0)


TURN = 90
"""Scans down the aisle before the drive turns back: 4.5 m, short of the room's east wall."""


def known_cells(m: OccupancyMap) -> set[tuple[int, int]]:
    """Known cells on the world's lattice (maps of different extent compare cell by cell)."""
    iy, ix = np.nonzero(m.occupancy >= 0)
    ox, oy = round(m.origin_x / m.resolution), round(m.origin_y / m.resolution)
    return set(zip((ix + ox).tolist(), (iy + oy).tolist()))


def mapped(scans: int) -> tuple[Mapper, Checkpoint]:
    """A mapper over ``scans`` scans down the aisle, and the checkpoint its deltas add up to
    (with the map handed back every tenth scan, as the worker does once a second)."""
    mapper, cp = Mapper(SlamConfig(), MOUNT, START), Checkpoint()
    for k in range(scans):
        s = scan_at(along_aisle(k))
        mapper.process(s.angles, s.ranges, along_aisle(k))
        cp.apply(mapper.delta())
        if k % 10 == 9:
            cp.map(mapper.occupancy())
    return mapper, cp


def test_the_deltas_add_up_to_the_mapper_state_and_are_empty_when_nothing_was_added():
    mapper, cp = mapped(40)
    assert mapper.keyframes >= 7  # 2 m at one per 0.25 m
    np.testing.assert_array_equal(cp.poses, mapper.graph.poses)
    assert cp.edges == mapper.graph.edges and len(cp.keyframe_points) == mapper.keyframes
    assert [s.index for s in cp.scans] == [s.index for s in mapper._scans]
    assert cp.counters[0] == 40
    s = scan_at(along_aisle(39))
    mapper.process(s.angles, s.ranges, along_aisle(39))  # standing still: nothing new to keep
    d = mapper.delta()
    assert len(d.poses) == 0 and not d.edges and not d.scans and d.occupancy is None and d.nbytes == 0


def test_a_solve_replaces_every_pose_and_brings_the_map_along():
    cp = Checkpoint(poses=np.zeros((3, 3)))
    occ = OccupancyMap(np.zeros((4, 4), dtype=np.int8), RES, 0.0, 0.0)
    cp.apply(Delta(0, np.ones((4, 3)), counters=(9, 1, 1, 5.0), occupancy=occ))
    assert cp.poses.shape == (4, 3) and (cp.poses == 1).all() and cp.occupancy is occ
    cp.apply(Delta(4, np.full((1, 3), 2.0)))  # then appends again
    assert cp.poses.shape == (5, 3) and cp.poses[-1, 0] == 2.0 and cp.occupancy is occ


def test_a_restored_mapper_starts_with_the_map_and_registers_its_first_scan_against_it():
    mapper, cp = mapped(40)
    here = along_aisle(40)
    off = Pose2D(here.x + 0.08, here.y - 0.05, 0.03)  # odometry's drift through the gap
    restored = Mapper.restored(SlamConfig(), MOUNT, cp, off)
    assert restored.keyframes == mapper.keyframes and restored.scans == 40
    np.testing.assert_array_equal(restored.occupancy().occupancy, cp.occupancy.occupancy)
    s = scan_at(here)
    pose = restored.process(s.angles, s.ranges, Pose2D())
    assert math.hypot(pose.x - here.x, pose.y - here.y) < 0.02 and abs(pose.yaw) < 0.01, pose
    for k in range(41, 60):  # and maps on, the graph growing from where it was
        s = scan_at(along_aisle(k))
        restored.process(s.angles, s.ranges, Pose2D(along_aisle(k).x - here.x))
    assert restored.keyframes > mapper.keyframes
    assert known_cells(cp.occupancy) <= known_cells(restored.occupancy())
    edge = restored.graph.edges[mapper.keyframes - 1]  # the first new keyframe hangs on the last kept one
    assert (edge.i, edge.j) == (mapper.keyframes - 1, mapper.keyframes)


class Drive:
    """A robot driving up and down the aisle at 0.5 m/s for a real worker, its scans stamped by
    the test's clock (0.1 s a tick); odometry is exact (the map frame is the odometry's). Up and
    down, not on for ever: past the room's end (4.5 m on) the scans see next to nothing, which
    SLAM passes over as blind, and a worker slow to start under load met only those."""

    def __init__(self):
        self.k = 0

    def pose(self) -> Pose2D:
        k = self.k % (2 * TURN)
        return along_aisle(k if k <= TURN else 2 * TURN - k)

    def odom(self) -> Pose2D:
        p = self.pose()
        return Pose2D(p.x - START.x, p.y - START.y, p.yaw)

    def scan(self):
        return scan_at(self.pose(), round(0.1 * self.k, 3))

    def tick(self, sup: SlamSupervisor) -> None:
        self.k += 1
        sup.tick(0.1 * self.k)


def drive(**cfg) -> tuple[Drive, SlamSupervisor]:
    robot = Drive()
    sup = SlamSupervisor(SlamConfig(**cfg), MOUNT, robot.odom, robot.scan)
    sup.tick(0.0)
    return robot, sup


@pytest.mark.parametrize("kind", ["spin", "block"])
def test_a_worker_wedged_for_real_is_replaced_by_one_that_goes_on_from_the_checkpoint(kind):
    robot, sup = drive(reply_timeout=0.5)
    try:
        for _ in range(25):
            robot.tick(sup)
        before, keyframes = sup.occupancy, sup.last_reply.keyframes
        sup.stall(kind)  # a busy loop, or a call that never returns, once this scan is answered
        while sup.deaths == 0 and robot.k < 40:
            robot.tick(sup)
        assert sup.deaths == 1 and sup.pid is None
        wedged_at = robot.k
        while sup.last_reply.stamp <= 0.1 * wedged_at and robot.k < wedged_at + 40:
            robot.tick(sup)
        assert sup.spawned == 2 and sup.restored == 1
        assert robot.k - wedged_at <= 12  # respawn_delay 1.0 s (10 ticks), then one exchange
        assert sup.last_reply.keyframes > keyframes  # the graph went on, it did not start again
        assert sup.last_reply.restore_s > 0
        assert known_cells(before) <= known_cells(sup.occupancy)  # the map handed back covers it
        here = along_aisle(sup.last_reply.stamp / 0.1)
        assert math.hypot(sup.last_reply.pose.x - (here.x - START.x), sup.last_reply.pose.y) < 0.02
    finally:
        sup.close()


def test_the_map_reset_still_starts_an_empty_map():
    robot, sup = drive()
    try:
        for _ in range(25):
            robot.tick(sup)
        keyframes = sup.last_reply.keyframes
        assert keyframes >= 4 and not sup.checkpoint.empty
        sup.reset(0.1 * robot.k)
        assert sup.checkpoint.empty
        reset_at = robot.k
        while sup.last_reply.stamp <= 0.1 * reset_at and robot.k < reset_at + 40:
            robot.tick(sup)
        assert sup.spawned == 2 and sup.restored == 0
        assert sup.last_reply.keyframes == 1  # a fresh graph: its first keyframe only
    finally:
        sup.close()


def test_free_running_hands_the_checkpoint_over_without_waiting_and_goes_on_from_it():
    """On the robot the tick never waits: the checkpoint goes to the new worker from a helper
    thread while the ticks return at once, and no scan is sent before it has arrived."""
    robot, sup = drive(lockstep=False, reply_timeout=0.5)

    def tick_until(cond, ticks=2000):
        for _ in range(ticks):  # real time passes (a real process answers), the robot drives
            robot.tick(sup)
            if cond():
                return True
            time.sleep(0.01)
        return False

    try:
        assert tick_until(lambda: sup.last_reply is not None and sup.last_reply.keyframes >= 4)
        keyframes = sup.last_reply.keyframes
        sup.stall("block")
        assert tick_until(lambda: sup.deaths == 1)
        assert tick_until(lambda: sup.restored == 1 and sup.last_reply.restore_s > 0)
        assert sup.spawned == 2 and sup.last_reply.keyframes >= keyframes  # nothing lost ...
        assert tick_until(lambda: sup.last_reply.keyframes > keyframes)  # ... and it maps on from there
        assert sup.spawned == 2
    finally:
        sup.close()
