"""A pose-graph correction reaches the map without stopping the scan loop (issue 30, item 4).

A robot drives down the synthetic greenhouse's aisle and back; on the way back a loop closure
is forced (the loop closer's search and match replaced by a match that pulls the chain 8 cm
north), so the graph is solved and the region it moved must be drawn again. The scan loop
keeps mapping every scan meanwhile, drawing at most ``BUDGET`` kept scans each; the map handed
out is the old one (plus the live scans) until the region is whole, then the moved one at once;
a worker lost mid-way is replaced by one that draws the region again from the checkpoint.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from hw.odometry import Pose2D
from nav.frames import compose, inverse, transform_points
from nav.slam.checkpoint import Checkpoint
from nav.slam.config import SlamConfig
from nav.slam.grid import LogOddsGrid
from nav.slam.loop_closure import LoopMatch
from nav.slam.mapper import Mapper
from nav.slam.rerender import BUDGET, touching
from nav.slam.scan_points import scan_points
from tests.nav.builders import RES, greenhouse_occupancy, scan_from_occupancy

OCC = greenhouse_occupancy()
MOUNT = Pose2D(0.115, 0.0, 0.0)
START = Pose2D(1.0, 0.5, 0.0)
CLOSE_AT = 100
"""The scan (on the way back) whose keyframe gets the forced loop closure."""


def at(k: int) -> Pose2D:
    """The robot after ``k`` scans: 60 east along the south aisle at 0.07 m a scan, then back."""
    x = 0.07 * (k if k < 60 else 119 - k)
    return Pose2D(START.x + x, START.y, 0.0 if k < 60 else math.pi)


def scan(k: int):
    p = at(k)
    lidar = compose(p, MOUNT)
    return scan_from_occupancy(OCC, RES, (lidar.x, lidar.y, lidar.yaw))


def odom(k: int) -> Pose2D:
    return compose(inverse(START), at(k))


def forced_closure(mapper: Mapper) -> None:
    """The next keyframe from scan ``CLOSE_AT`` on closes a loop onto the first keyframe, its
    pose there put 8 cm north of where the chain has it: a solve that moves the chain."""
    def candidate(poses, travel, k):
        return 0 if mapper.scans >= CLOSE_AT and mapper.solves == 0 else None

    def match(poses, scans, c, k):
        first, here = (Pose2D(*poses[i]) for i in (c, k))
        return LoopMatch(c, compose(inverse(first), Pose2D(here.x, here.y + 0.08, here.yaw)), 0.08, 1.0)

    mapper.loops.candidate, mapper.loops.match = candidate, match


def live(grid: LogOddsGrid, mapper: Mapper, k: int) -> None:
    """Scan ``k`` drawn at the pose the mapper gave it, as the live grid takes every scan."""
    s = scan(k)
    pts = scan_points(s.angles, s.ranges, MOUNT, 0.25, 12.0)
    sensor = compose(mapper.pose, MOUNT)
    grid.integrate((sensor.x, sensor.y), transform_points(mapper.pose, pts[:, :2]))


def test_a_forced_loop_closure_reaches_the_map_whole_a_bounded_share_per_scan_while_scans_go_on():
    mapper = Mapper(SlamConfig(), MOUNT, Pose2D())
    forced_closure(mapper)
    old_map, pending_scans, swapped = None, 0, None
    for k in range(120):
        before, drawn = copy.deepcopy(mapper.grid), mapper.rerendered
        s = scan(k)
        mapper.process(s.angles, s.ranges, odom(k))
        assert mapper.rerendered - drawn <= BUDGET  # the work a scan does for a correction is bounded
        if mapper.solves and old_map is None:  # the solve: from here the old map goes on live
            old_map, region = before, mapper.rerendering.region
        if old_map is not None and swapped is None:
            live(old_map, mapper, k)
            if mapper.rerendering is not None:  # pending: the map handed out is the old one, live
                pending_scans += 1
                assert np.array_equal(mapper.occupancy().occupancy, old_map.occupancy().occupancy)
            else:
                swapped, at_swap = k, mapper.occupancy()
    assert mapper.solves == 1 and mapper.swaps == 1 and swapped is not None and mapper.scans == 120
    assert pending_scans >= 2  # the drawing was spread over scans, each one mapped meanwhile
    # then the region is, at once, every kept scan that reaches it drawn at its corrected pose
    redrawn = LogOddsGrid(region)
    for kept in mapper._scans:
        pose = compose(mapper.graph.node(kept.keyframe), kept.relative)
        if kept.index <= swapped and touching(region, np.array([[pose.x, pose.y]]), np.array([kept.reach]))[0]:
            sensor = compose(pose, MOUNT)
            redrawn.integrate((sensor.x, sensor.y), transform_points(pose, kept.points.astype(np.float64)),
                              redrawn.whole)
    dx, dy = region.offset_in(at_swap.geometry)
    window = (slice(dy, dy + region.height), slice(dx, dx + region.width))
    np.testing.assert_array_equal(at_swap.occupancy[window], redrawn.occupancy().occupancy)
    assert (at_swap.occupancy[window] != old_map.occupancy().occupancy[window]).sum() > 20  # it moved
    outside = np.ones(at_swap.occupancy.shape, bool)
    outside[window] = False  # and nothing outside it did
    np.testing.assert_array_equal(at_swap.occupancy[outside], old_map.occupancy().occupancy[outside])


def test_a_worker_lost_mid_way_through_a_redraw_is_replaced_by_one_that_draws_it_again():
    mapper, cp = Mapper(SlamConfig(), MOUNT, Pose2D()), Checkpoint()
    forced_closure(mapper)
    k = 0
    while mapper.rerendering is None:
        s = scan(k)
        mapper.process(s.angles, s.ranges, odom(k))
        cp.apply(mapper.delta())
        cp.map(mapper.occupancy())
        k += 1
    assert cp.rerender == mapper.rerendering.bounds and cp.occupancy is not None
    restored = Mapper.restored(SlamConfig(), MOUNT, cp, mapper.pose)
    assert restored.rerendering is not None and restored.rerendering.region == mapper.rerendering.region
    assert len(restored.rerendering.queue) >= len(mapper.rerendering.queue)
    for j in range(k, 120):
        s = scan(j)
        restored.process(s.angles, s.ranges, odom(j))
        cp.apply(restored.delta())
        if restored.rerendering is None:
            break
    assert restored.swaps == 1 and cp.rerender is None
    np.testing.assert_array_equal(cp.occupancy.occupancy, restored.occupancy().occupancy)


def test_a_map_to_keep_has_the_pending_redraw_finished_first():
    mapper = Mapper(SlamConfig(), MOUNT, Pose2D())
    forced_closure(mapper)
    k = 0
    while mapper.rerendering is None:
        s = scan(k)
        mapper.process(s.angles, s.ranges, odom(k))
        k += 1
    pending, drawn = len(mapper.rerendering.queue), mapper.rerendered
    assert pending > BUDGET  # more than one scan's share is left
    mapper.settle()  # a patrol's end or a map save: the map handed back is the moved one
    assert mapper.rerendering is None and mapper.swaps == 1 and mapper.rerendered - drawn == pending
    assert mapper.delta().occupancy is not None  # and the checkpoint takes it
