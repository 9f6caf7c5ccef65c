"""Frontier exploration (Yamauchi, "A frontier-based approach for autonomous exploration", 1997):
drive to the nearest place where the mapped floor meets ground never seen, until there is none.

A *frontier cell* is a free cell of the SLAM map (map_server free: 0..25) with an unknown
4-neighbour; 8-connected frontier cells make a frontier. Small frontiers are noise, not rooms:
the shadow a pot casts on the floor behind it closes as soon as the robot moves, so a frontier
counts only with ``min_cells`` cells or more (0.5 m of boundary at 0.05 m). The nearest is
nearest *by path*: one NavFn wavefront from the robot over the global costmap gives every cell's
path cost, and the goal is the frontier cell the robot can reach most cheaply, among those the
robot's body fits on (costmap below inscribed). Frontiers the navigator failed to reach are left
out (``blocked``), so a doorway too narrow to pass does not hold the exploration forever.
"""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from nav.costmap.grid import INSCRIBED, CostGrid
from nav.grid_geometry import paste
from nav.occupancy import FREE_MAX, OccupancyMap
from nav.planner import NEUTRAL, OBSTACLE, POT_HIGH, crossing_costs, propagate

@dataclass(frozen=True)
class Frontier:
    x: float
    y: float
    """The goal: the frontier's cell the robot reaches most cheaply, map frame, m."""
    cells: int
    """The frontier's size in cells."""
    path_cost: float
    """NavFn potential to the goal over the neutral cost: roughly metres of free floor."""


def frontier_clusters(occupancy: OccupancyMap, min_cells: int) -> list[np.ndarray]:
    """Each frontier of ``min_cells`` cells or more, as (N, 2) cell indices (ix, iy)."""
    occ = occupancy.occupancy
    free = (occ >= 0) & (occ <= FREE_MAX)
    unknown = (occ < 0).astype(np.uint8)
    near_unknown = cv2.dilate(unknown, np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)) > 0
    cells = (free & near_unknown).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(cells, connectivity=8)
    out = []
    for k in range(1, n):
        if stats[k, cv2.CC_STAT_AREA] >= min_cells:
            iy, ix = np.nonzero(labels == k)
            out.append(np.column_stack([ix, iy]))
    return out


def nearest_frontier(occupancy: OccupancyMap, costmap: CostGrid, robot_xy: tuple[float, float], min_cells: int,
                     blocked: list[tuple[float, float]] = (), blocked_radius: float = 0.5) -> Frontier | None:
    """The frontier the robot reaches most cheaply, or None when none is left (or reachable)."""
    clusters = frontier_clusters(occupancy, min_cells)
    if not clusters:
        return None
    geo = costmap.geometry
    x0, x1, y0, y1 = occupancy.geometry.extent
    big = geo.grown_to_cover(min(x0, robot_xy[0]), min(y0, robot_xy[1]), max(x1, robot_xy[0]), max(y1, robot_xy[1]))
    data = paste(costmap.data, geo, big, 255)
    h, w = data.shape
    framed = np.full((h + 2, w + 2), OBSTACLE, np.uint8)
    framed[1:-1, 1:-1] = crossing_costs(data, allow_unknown=True)
    rx, ry = (int(v) for v in big.cell_of(*robot_xy))
    framed[ry + 1, rx + 1] = NEUTRAL  # the robot's own cell is where it stands
    pot = propagate(framed.ravel(), w + 2, (ry + 1) * (w + 2) + rx + 1, -1).reshape(h + 2, w + 2)[1:-1, 1:-1]
    best: Frontier | None = None
    for cells in clusters:
        wx, wy = occupancy.geometry.centre_of(cells[:, 0], cells[:, 1])
        bx, by = big.cell_of(wx, wy)
        inside = big.contains(bx, by)
        wx, wy, bx, by = wx[inside], wy[inside], bx[inside], by[inside]
        cost = np.where(data[by, bx] < INSCRIBED, pot[by, bx], POT_HIGH)
        for bxy in blocked:
            cost[np.hypot(wx - bxy[0], wy - bxy[1]) <= blocked_radius] = POT_HIGH
        if not len(cost) or cost.min() >= POT_HIGH:
            continue
        k = int(np.argmin(cost))
        candidate = Frontier(float(wx[k]), float(wy[k]), len(cells), float(cost[k]) / NEUTRAL * geo.resolution)
        if best is None or candidate.path_cost < best.path_cost:
            best = candidate
    return best
