"""The relocation search ranks its candidates on a raster of the local map (nav/slam/relocate.py
``Raster``): a point counted there lies within about ``INLIER`` of the map, as the exact test
says, bracketed by it at a tighter and a looser distance."""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D
from nav.slam.planar_icp import VoxelMap
from nav.slam.relocate import CELL, INLIER, NEAR, Raster, _raster_scores, _scores

ROOM = np.array([(x, 0.0) for x in np.arange(0, 8, 0.02)] + [(0.0, y) for y in np.arange(0, 5, 0.02)]
                + [(3.0 + 0.3 * math.cos(a), 2.0 + 0.3 * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 90)])


def room_map() -> VoxelMap:
    m = VoxelMap(0.1, 12.0, 3)
    m.add(ROOM)
    return m


def test_every_map_point_is_on_the_raster_and_open_floor_is_not():
    raster = Raster.of(room_map())

    def on(x, y):
        return bool(raster.near[int(math.floor((y - raster.y0) / CELL)), int(math.floor((x - raster.x0) / CELL))])

    assert all(on(x, y) for x, y in ROOM)
    assert not on(1.5, 1.5) and not on(3.0, 2.0) and not on(0.3, 0.3)  # open floor, a big pot's middle


def test_the_ranking_counts_lie_between_the_exact_counts_near_and_far():
    m, rng = room_map(), np.random.default_rng(3)
    scan = ROOM[::3] - (2.0, 1.5) + rng.normal(0, 0.02, (len(ROOM[::3]), 2))  # seen from (2, 1.5), noisy
    raster, guess = Raster.of(m), Pose2D(2.1, 1.4, 0.05)
    ranked = _raster_scores(scan, raster.near, raster.x0, raster.y0, CELL, guess.x, guess.y, guess.yaw,
                            NEAR.offsets, NEAR.turns)
    tight = _scores(scan, m.keys, m.count, m.points, m.voxel, guess.x, guess.y, guess.yaw, NEAR.offsets, NEAR.turns, CELL)
    loose = _scores(scan, m.keys, m.count, m.points, m.voxel, guess.x, guess.y, guess.yaw, NEAR.offsets, NEAR.turns,
                    (math.ceil(INLIER / CELL) + 1) * CELL * math.sqrt(2))
    assert (tight <= ranked).all() and (ranked <= loose).all()
    best = np.unravel_index(np.argmax(ranked), ranked.shape)
    dx, dy = NEAR.offsets[best[0]]
    assert math.hypot(guess.x + dx - 2.0, guess.y + dy - 1.5) <= 0.1 and abs(guess.yaw + NEAR.turns[best[1]]) <= 0.05
