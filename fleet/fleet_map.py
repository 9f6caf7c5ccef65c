"""The map the dispatcher splits the pots on, in the fleet's frame (the mission's: the first dock's).

On a farm it is a saved map (``lupin fleet patrol --map MAP.yaml``, one ``lupin patrol`` or
``lupin map save`` wrote from the first dock). In the sim the dispatcher has no robot's map
before the patrol (each robot maps from its dock as it drives), so it draws the world file as a
grower would draw the greenhouse's floor plan (``plan_of_world``): walls round the floor, each pot
a disc, each box; no people, nothing the sim moves. That is the file the sim was built from, not
the sim's state: the robots still find everything themselves.

``cost_grid`` inflates either into what the planner measures path lengths on (``nav.path_lengths``),
with the robot's footprint and inflation from the runtime's own costmap settings.
"""
from __future__ import annotations

import math

import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import FREE, LETHAL, CostGrid
from nav.costmap.inflation import InflationLayer
from nav.occupancy import OccupancyMap

OCCUPIED = 100
WALL = 0.3
"""The plan's margin round the floor, m: walls, drawn occupied, so the map's edge is a wall."""
POT_RADIUS = 0.10
"""A pot's radius in the plan, m (spec/world.md: ~0.10 m)."""


def plan_of_world(world, origin: tuple[float, float, float], resolution: float = 0.05) -> OccupancyMap:
    """``world`` (a ``sim.world.World``) drawn as an occupancy map in the frame whose origin is
    ``origin`` (x, y, yaw in the world: the first dock), axis-aligned in that frame."""
    ox, oy, oyaw = origin
    c, s = math.cos(oyaw), math.sin(oyaw)
    fx, fy = world.floor.x, world.floor.y
    corners = np.array([(x, y) for x in (-WALL, fx + WALL) for y in (-WALL, fy + WALL)]) - (ox, oy)
    local = np.c_[c * corners[:, 0] + s * corners[:, 1], -s * corners[:, 0] + c * corners[:, 1]]
    lo, hi = local.min(axis=0), local.max(axis=0)
    w, h = (np.ceil((hi - lo) / resolution)).astype(int)
    u = lo[0] + (np.arange(w) + 0.5) * resolution
    v = lo[1] + (np.arange(h) + 0.5) * resolution
    uu, vv = np.meshgrid(u, v)  # cell centres in the fleet's frame, [iy, ix]
    wx, wy = ox + c * uu - s * vv, oy + s * uu + c * vv  # ... in the world's
    blocked = (wx < 0) | (wx > fx) | (wy < 0) | (wy > fy)
    for p in world.pots:
        blocked |= np.hypot(wx - p.x, wy - p.y) <= POT_RADIUS
    for b in world.obstacles:
        bc, bs = math.cos(b.yaw), math.sin(b.yaw)
        dx, dy = wx - b.x, wy - b.y
        blocked |= (np.abs(bc * dx + bs * dy) <= b.sx / 2) & (np.abs(-bs * dx + bc * dy) <= b.sy / 2)
    return OccupancyMap(np.where(blocked, OCCUPIED, 0).astype(np.int8), resolution, float(lo[0]), float(lo[1]))


def cost_grid(m: OccupancyMap, costmap: CostmapsConfig) -> CostGrid:
    """``m`` inflated as the global costmap's static layer would be (unknown ground counted
    open, as ``order: shortest`` counts it)."""
    master = np.where(m.occupancy >= 65, LETHAL, FREE).astype(np.uint8)
    inflated = InflationLayer(m.resolution, costmap.robot_radius, costmap.inflation_radius,
                              costmap.cost_scaling_factor).apply(master)
    return CostGrid(inflated, m.resolution, m.origin_x, m.origin_y)
