"""Shared builders for navigation tests: a dummy costmap, a straight path, a tiny greenhouse,
and a lidar scan ray-marched through an occupancy grid (the one thing a unit test needs that
would otherwise take the simulator)."""
from __future__ import annotations

import cv2
import numpy as np

from hw.interfaces import LidarScan
from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import FREE, LETHAL, CostGrid
from nav.costmap.inflation import InflationLayer

RES = 0.05


def dummy_costmap(width: int = 60, height: int = 60, value: int = FREE, origin=(0.0, 0.0),
                  resolution: float = RES) -> CostGrid:
    """A uniform grid (free by default) to draw on."""
    return CostGrid.filled(width, height, resolution, origin[0], origin[1], value)


def straight_path(start=(0.0, 0.0), end=(2.0, 0.0), step: float = RES) -> np.ndarray:
    """(N, 2) points from ``start`` to ``end`` about ``step`` apart, both ends included."""
    n = max(int(np.ceil(np.hypot(end[0] - start[0], end[1] - start[1]) / step)), 1)
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    return (1 - t) * np.asarray(start, float) + t * np.asarray(end, float)


def greenhouse_occupancy(floor=(7.0, 4.0), rows=(1.0, 2.0, 3.0), pots_x=(2.0, 3.0, 4.0, 5.0),
                         pot_radius: float = 0.10, resolution: float = RES) -> np.ndarray:
    """A map_server occupancy grid (int8, 0 free / 100 occupied) of the built-in greenhouse's
    layout: walls round a 7 x 4 m floor, pots 1 m apart in rows 1 m apart (0.8 m aisles)."""
    w, h = int(round(floor[0] / resolution)), int(round(floor[1] / resolution))
    occ = np.zeros((h, w), dtype=np.uint8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    yy, xx = np.mgrid[0:h, 0:w]
    cx, cy = (xx + 0.5) * resolution, (yy + 0.5) * resolution
    for py in rows:
        for px in pots_x:
            occ[np.hypot(cx - px, cy - py) <= pot_radius] = 100
    return occ.astype(np.int8)


def greenhouse_grid(cfg: CostmapsConfig | None = None) -> CostGrid:
    """The tiny greenhouse as an inflated cost grid (origin at the floor's corner)."""
    cfg = cfg or CostmapsConfig()
    occ = greenhouse_occupancy(resolution=cfg.resolution)
    master = np.where(occ >= 65, LETHAL, FREE).astype(np.uint8)
    inflated = InflationLayer(cfg.resolution, cfg.robot_radius, cfg.inflation_radius,
                              cfg.cost_scaling_factor).apply(master)
    return CostGrid(inflated, cfg.resolution, 0.0, 0.0)


def scan_from_occupancy(occupancy: np.ndarray, resolution: float, pose, beams: int = 500,
                        max_range: float = 12.0, origin=(0.0, 0.0)) -> LidarScan:
    """A lidar revolution from ``pose`` (x, y, yaw) in the occupancy grid's frame: each beam
    marches in quarter-cell steps to the first occupied cell (inf when none within range)."""
    angles = np.linspace(-np.pi, np.pi, beams, endpoint=False).astype(np.float32)
    r = np.arange(0.0, max_range, resolution / 4)
    a = pose[2] + angles.astype(np.float64)
    x = pose[0] + np.cos(a)[:, None] * r[None, :]
    y = pose[1] + np.sin(a)[:, None] * r[None, :]
    ix = np.floor((x - origin[0]) / resolution).astype(int)
    iy = np.floor((y - origin[1]) / resolution).astype(int)
    h, w = occupancy.shape
    inside = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
    occ = np.zeros(ix.shape, dtype=bool)
    occ[inside] = occupancy[iy[inside], ix[inside]] >= 65
    first = np.where(occ.any(axis=1), occ.argmax(axis=1), -1)
    ranges = np.where(first >= 0, r[np.maximum(first, 0)], np.inf).astype(np.float32)
    return LidarScan(0.0, angles, ranges)


def box_occupancy(shape=(80, 80), box=(50, 30, 55, 50)) -> np.ndarray:
    """A free occupancy grid with one occupied rectangle (ix0, iy0, ix1, iy1), ends exclusive."""
    occ = np.zeros(shape, dtype=np.int8)
    x0, y0, x1, y1 = box
    occ[y0:y1, x0:x1] = 100
    return occ


def draw_disc(grid: CostGrid, x: float, y: float, radius: float, value: int = LETHAL) -> CostGrid:
    """Draw a filled disc (world coordinates) into ``grid`` in place; returns it."""
    ix, iy = grid.geometry.cell_of(x, y)
    cv2.circle(grid.data, (int(ix), int(iy)), int(round(radius / grid.resolution)), int(value), -1)
    return grid


def covered(angles: np.ndarray, ranges: np.ndarray) -> np.ndarray:
    """``ranges`` as a cart pushed over the robot leaves them: nothing from the front arc
    (+-60 deg, under range_min), the cart's face 0.3 m to the left along the robot (60-120 deg)."""
    a = np.angle(np.exp(1j * np.asarray(angles, dtype=np.float64)))
    out = np.asarray(ranges).copy()
    out[np.abs(a) <= np.radians(60)] = np.inf
    side = (a > np.radians(60)) & (a < np.radians(120))
    out[side] = 0.3 / np.sin(a[side])
    return out
