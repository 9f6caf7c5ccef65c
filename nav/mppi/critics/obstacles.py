"""ObstaclesCritic (seed: critical weight 20.0, collision cost 10000, circular footprint).

Per trajectory point, the cost of the costmap cell under the robot's centre:

- lethal (254) or inscribed (253: with ``consider_footprint: false`` the centre there means
  contact), or off the local map / unknown (the local costmap does not track unknown space, so
  Nav2 counts no information as collision): the whole trajectory costs ``collision_cost``;
- otherwise the inflated cost is turned back into a distance to the obstacle past the
  footprint, inverting the inflation formula ``cost = 252 exp(-k (d - r))``; closer than
  ``collision_margin_distance`` (0.10 m) adds ``margin - d`` (critical), and every such point
  adds a repulsion ``inflation_radius - d`` unless the robot is within 0.5 m of the goal
  (approach poses sit near pots). With the seed's thin halo (0.25 m, k 5.0) every inflated
  cell is within 0.03 m of the footprint, so both terms apply to all of them;
- free cells (0) add nothing.

Total: ``critical_weight * critical + repulsion_weight * (rep - min rep) / T`` (reference).
One numba pass per trajectory with the per-cost terms precomputed for 0..255 (a trajectory
stops being scored at its first collision, as in Nav2).
Sets ``data.fail`` when every trajectory collides.
"""
from __future__ import annotations

import numba
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
        self._repulsion = np.where(inflated, costmaps.inflation_radius - dist, 0.0).astype(np.float32)
        self._collides = np.zeros(256, dtype=bool)
        self._collides[[INSCRIBED, LETHAL, UNKNOWN]] = True

    def score(self, data: CriticData) -> None:
        p, g = self.params, data.grid
        collide, critical, rep = _scan(data.traj[0], data.traj[1], g.data, np.float32(g.origin_x),
                                       np.float32(g.origin_y), np.float32(1.0 / g.resolution),
                                       self._collides, self._critical, self._repulsion)
        total = p.critical_weight * np.where(collide, np.float32(p.collision_cost), critical)
        if data.goal_distance > p.near_goal_distance:
            total = total + p.repulsion_weight * (rep - rep.min()) / data.traj.shape[2]
        data.costs += total.astype(np.float32)
        data.fail = bool(collide.all())


@numba.njit(cache=True, fastmath=True)
def _scan(x, y, grid, ox, oy, inv_res, collides, critical_lut, repulsion_lut):
    """One pass over every trajectory point: the cell under it (off the map = unknown), whether
    the trajectory collides, and its summed critical and repulsion terms."""
    b, t = x.shape
    h, w = grid.shape
    collide = np.zeros(b, np.bool_)
    critical = np.zeros(b, np.float32)
    rep = np.zeros(b, np.float32)
    for k in range(b):
        c_sum, r_sum = 0.0, 0.0
        for i in range(t):
            ix = int(np.floor((x[k, i] - ox) * inv_res))
            iy = int(np.floor((y[k, i] - oy) * inv_res))
            cost = grid[iy, ix] if (0 <= ix < w and 0 <= iy < h) else 255
            if collides[cost]:
                collide[k] = True
                break
            c_sum += critical_lut[cost]
            r_sum += repulsion_lut[cost]
        critical[k] = c_sum
        rep[k] = r_sum
    return collide, critical, rep
