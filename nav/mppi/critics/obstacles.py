"""ObstaclesCritic (seed: critical weight 20.0, collision cost 10000, circular footprint).

Per trajectory point, the cost of the costmap cell under the robot's centre:

- lethal (254) or inscribed (253: with ``consider_footprint: false`` the centre there means
  contact), or off the local map / unknown (the local costmap does not track unknown space, so
  Nav2 counts no information as collision): the whole trajectory costs ``collision_cost``;
- otherwise the inflated cost is turned back into a distance to the obstacle past the
  footprint, inverting the inflation formula ``cost = 252 exp(-k (d - r))``; closer than
  ``collision_margin_distance`` (0.10 m) adds ``margin - d`` (critical), farther adds a
  repulsion ``inflation_radius - d`` unless the robot is within 0.5 m of the goal (approach
  poses sit near pots);
- free cells (0) add nothing.

Total: ``critical_weight * critical + repulsion_weight * (rep - min rep) / T`` (reference).
All of it is three table lookups per point: the per-cost terms are precomputed for 0..255.
Sets ``data.fail`` when every trajectory collides.
"""
from __future__ import annotations

import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import INSCRIBED, LETHAL, UNKNOWN
from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class ObstaclesCritic(Critic):
    def __init__(self, params, costmaps: CostmapsConfig):
        super().__init__(params, costmaps)
        k = costmaps.cost_scaling_factor
        c = np.arange(256, dtype=np.float64)
        inflated = (c >= 1) & (c <= 252)
        dist = np.where(inflated, (np.log(253.0) - np.log(np.maximum(c, 1.0))) / k, np.inf)
        margin = params.collision_margin_distance
        self._critical = np.where(inflated & (dist < margin), margin - dist, 0.0).astype(np.float32)
        self._repulsion = np.where(inflated & (dist >= margin), costmaps.inflation_radius - dist, 0.0).astype(np.float32)
        self._collides = np.zeros(256, dtype=bool)
        self._collides[[INSCRIBED, LETHAL, UNKNOWN]] = True

    def cell_costs(self, data: CriticData) -> np.ndarray:
        """Cost of the cell under every trajectory point, (B, T) uint8; off the map = unknown."""
        g = data.grid
        inv = np.float32(1.0 / g.resolution)
        ix = np.floor((data.traj[0] - np.float32(g.origin_x)) * inv).astype(np.int32)
        iy = np.floor((data.traj[1] - np.float32(g.origin_y)) * inv).astype(np.int32)
        h, w = g.data.shape
        inside = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
        flat = np.where(inside, iy * w + ix, 0)
        return np.where(inside, g.data.ravel()[flat], np.uint8(UNKNOWN))

    def score(self, data: CriticData) -> None:
        p = self.params
        cost = self.cell_costs(data)
        collide = self._collides[cost].any(axis=1)
        critical = self._critical[cost].sum(axis=1)
        raw = np.where(collide, np.float32(p.collision_cost), critical)
        total = p.critical_weight * raw
        if data.goal_distance > p.near_goal_distance:
            rep = self._repulsion[cost].sum(axis=1)
            total = total + p.repulsion_weight * (rep - rep.min()) / cost.shape[1]
        data.costs += total.astype(np.float32)
        data.fail = bool(collide.all())
