"""PathAlignCritic (seed weight 14.0, dominant): hug the global path.

For every ``trajectory_point_step``-th (4th) point of each trajectory, the distance to the path
point with the closest cumulative arc length (so a trajectory is compared with the stretch of
path it would have covered, not with whichever path point happens to be nearest); the mean of
those distances. Skipped until the trajectories reach ``offset_from_furthest`` (20) path
points, within 0.5 m of the goal, and when more than 7 % of the path up to the furthest point
is lethal, inscribed or unknown (something stands on the path: avoid it, do not align through).
"""
from __future__ import annotations

import numpy as np

from nav.costmap.grid import INSCRIBED
from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class PathAlignCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance <= p.threshold_to_consider:
            return
        furthest = data.furthest_reached
        if furthest < p.offset_from_furthest:
            return
        path = data.path[: furthest + 1]
        occupied = data.grid.cost_at(path[:, 0], path[:, 1]) >= INSCRIBED
        if occupied.mean() > p.max_path_occupancy_ratio:
            return
        path_cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path[:, :2], axis=0).T))]).astype(np.float32)
        # Arc length measured between the sampled points only, as Nav2 does (4x fewer hypots).
        cols = slice(p.trajectory_point_step - 1, None, p.trajectory_point_step)
        sx, sy = data.traj[0][:, cols], data.traj[1][:, cols]
        dx = np.diff(sx, axis=1, prepend=np.float32(data.pose[0]))
        dy = np.diff(sy, axis=1, prepend=np.float32(data.pose[1]))
        s = np.cumsum(np.hypot(dx, dy), axis=1)
        hi = np.clip(np.searchsorted(path_cum, s), 1, len(path_cum) - 1)
        nearer_lo = (s - path_cum[hi - 1]) < (path_cum[hi] - s)
        idx = np.where(nearer_lo, hi - 1, hi)
        d = np.hypot(sx - path[idx, 0].astype(np.float32), sy - path[idx, 1].astype(np.float32))
        data.costs += p.weight * d.mean(axis=1)
