"""The looks beside a pot's taken approach pose (``mission.patrol.aside``): on the plate's side
only, where the robot fits, nearest the robot first; the square look from farther out when
nothing stands there."""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D
from mission.patrol.aside import FARTHER, SLANTS, aside_detail, aside_looks
from nav.config import NavConfig
from nav.costmap.grid import INSCRIBED
from nav.costmap.layered import global_costmap

RES, X0, Y0 = 0.05, -2.0, -1.0
POT = (0.0, 0.0, math.pi / 2)
"""A pot at the origin, its plate facing +y: its approach pose is (0, 0.5)."""


def floor(*boxes: tuple[float, float, float, float]):
    """4 x 3 m of explored floor with occupied boxes (x0, y0, x1, y1) and the pot."""
    occupancy = np.zeros((60, 80), np.int8)
    for x0, y0, x1, y1 in ((-0.1, -0.1, 0.1, 0.1), *boxes):
        occupancy[int((y0 - Y0) / RES):int((y1 - Y0) / RES) + 1, int((x0 - X0) / RES):int((x1 - X0) / RES) + 1] = 100
    cm = global_costmap(NavConfig().costmap)
    cm.set_static(occupancy, RES, X0, Y0)
    return cm.grid


def bearings(looks: list[Pose2D]) -> list[float]:
    """Each look's bearing from the pot, off the plate's facing (rad)."""
    return [math.remainder(math.atan2(p.y, p.x) - POT[2], 2 * math.pi) for p in looks]


def test_with_nothing_in_the_way_every_look_on_the_plates_side_is_offered_facing_the_pot():
    looks = aside_looks(*POT, 0.5, floor(), Pose2D(-1.0, 0.5, 0.0))
    assert len(looks) == 2 * len(SLANTS) + 2 * len(SLANTS) + 1  # both hands at both rings, square from farther out
    assert max(abs(b) for b in bearings(looks)) <= max(SLANTS) + 1e-9
    for p in looks:
        assert min(abs(math.hypot(p.x, p.y) - r) for r in (0.5, 0.5 + FARTHER)) < 1e-9  # either ring
        assert abs(math.remainder(p.yaw - math.atan2(-p.y, -p.x), 2 * math.pi)) < 1e-9  # looking at the pot
    gaps = [math.hypot(p.x + 1.0, p.y - 0.5) for p in looks]
    assert gaps == sorted(gaps) and looks[0].x < 0  # nearest the robot (west of the pot) first


def test_a_crate_on_the_approach_pose_leaves_only_the_looks_beside_it():
    grid = floor((-0.15, 0.35, 0.15, 0.65))  # a 0.3 m crate on (0, 0.5)
    looks = aside_looks(*POT, 0.5, grid, Pose2D(1.0, 0.5, math.pi))
    assert looks and all(int(grid.cost_at(p.x, p.y)) < INSCRIBED for p in looks)
    assert min(abs(b) for b in bearings(looks)) >= 0.5  # none square on or nearly: the crate is there
    assert looks[0].x > 0  # the robot stands east of it: the east side first


def test_no_room_beside_it_no_looks_and_the_report_says_where_it_stood():
    assert aside_looks(*POT, 0.5, floor((-0.9, 0.2, 0.9, 0.7)), Pose2D(-1.0, 0.5, 0.0)) == []
    words = aside_detail(Pose2D(0.0, 0.5, -math.pi / 2), Pose2D(0.5, 0.3, -math.pi / 2 - 1.1), "no progress")
    assert words == "something stood on its approach pose (no progress): inspected from 0.54 m off it, turned 63 deg"
