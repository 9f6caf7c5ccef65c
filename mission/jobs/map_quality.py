"""How good is a map: its occupied cells against the world file, rasterised on the map's grid.

Judging only (it reads the sim's world, which the robot never does). The truth is what a lidar
in the greenhouse could see: the faces of pots, boxes and walls, i.e. the cells of the
rasterised solids that border the free floor. The map's occupied cells (p >= 0.65, map_server's
threshold) are then scored both ways with a one-cell tolerance:

* recall: the share of true face cells with a mapped occupied cell within one cell;
* precision: the share of mapped occupied cells with a true solid cell within one cell.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from hw.odometry import Pose2D
from nav.occupancy import OccupancyMap
from sim.config import GreenhouseGeometry
from sim.greenhouse import WALL_THICKNESS
from sim.world import World

_NEIGHBOURS = np.ones((3, 3), np.uint8)


@dataclass(frozen=True)
class MapQuality:
    recall: float
    precision: float
    true_cells: int
    mapped_cells: int


def solid_cells(m: OccupancyMap, world: World, spawn: Pose2D,
                geometry: GreenhouseGeometry = GreenhouseGeometry()) -> tuple[np.ndarray, np.ndarray]:
    """Boolean [iy, ix] rasters on ``m``'s grid: (solid, floor) from the world file; the map
    frame is the robot's start pose ``spawn`` (world frame)."""
    ix, iy = np.meshgrid(np.arange(m.width), np.arange(m.height))
    mx, my = m.geometry.centre_of(ix, iy)
    c, s = math.cos(spawn.yaw), math.sin(spawn.yaw)
    wx, wy = spawn.x + c * mx - s * my, spawn.y + s * mx + c * my
    fx, fy = world.floor.x, world.floor.y
    floor = (wx >= 0) & (wx <= fx) & (wy >= 0) & (wy <= fy)
    t = WALL_THICKNESS
    solid = ~floor & (wx >= -t) & (wx <= fx + t) & (wy >= -t) & (wy <= fy + t)
    for pot in world.pots:
        solid |= np.hypot(wx - pot.x, wy - pot.y) <= geometry.pot_radius
    for box in world.obstacles:
        bc, bs = math.cos(box.yaw), math.sin(box.yaw)
        lx, ly = bc * (wx - box.x) + bs * (wy - box.y), -bs * (wx - box.x) + bc * (wy - box.y)
        solid |= (np.abs(lx) <= box.sx / 2) & (np.abs(ly) <= box.sy / 2)
    return solid, floor & ~solid


def map_quality(m: OccupancyMap, world: World, spawn: Pose2D) -> MapQuality:
    solid, free = solid_cells(m, world, spawn)
    faces = solid & (cv2.dilate(free.astype(np.uint8), np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)) > 0)
    mapped = m.occupied()
    near_mapped = cv2.dilate(mapped.astype(np.uint8), _NEIGHBOURS) > 0
    near_solid = cv2.dilate(solid.astype(np.uint8), _NEIGHBOURS) > 0
    n_true, n_mapped = int(faces.sum()), int(mapped.sum())
    return MapQuality(recall=float((faces & near_mapped).sum()) / max(n_true, 1),
                      precision=float((mapped & near_solid).sum()) / max(n_mapped, 1),
                      true_cells=n_true, mapped_cells=n_mapped)
