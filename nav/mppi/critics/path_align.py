"""PathAlignCritic (seed weight 14.0, dominant): hug the global path.

Walking each trajectory from the robot's pose, every ``trajectory_point_step``-th (4th) point is
compared with the path point whose cumulative arc length is closest to the arc length the
trajectory has covered so far (so a trajectory is compared with the stretch of path it would
have covered, not with whichever path point happens to be nearest); the cost is the mean of
those distances over the samples whose path point is not blocked. Skipped until the
trajectories reach ``offset_from_furthest`` (20) path points, within 0.5 m of the goal, and
when more than 7 % of the path up to the furthest point is lethal, inscribed or unknown
(something stands on the path: avoid it, do not align through). Nav2 measures the arc length
from each trajectory's first point, one step ahead of the robot; measuring it from the robot's
pose, where the pruned path starts, removes that one-step bias.

The arc-length match walks the path forward with one pointer per trajectory (arc length only
grows), a sequential scan numpy cannot express without a (B, samples, N) search; one numba
pass does it (``lupin bench nav.mppi`` prints the per-critic times).
"""
from __future__ import annotations

import numba
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
        valid = data.grid.cost_at(path[:, 0], path[:, 1]) < INSCRIBED
        if 1.0 - valid.mean() > p.max_path_occupancy_ratio:
            return
        px, py = path[:, 0].astype(np.float32), path[:, 1].astype(np.float32)
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(px), np.diff(py)))]).astype(np.float32)
        x0, y0 = np.float32(data.pose[0]), np.float32(data.pose[1])
        data.costs += p.weight * _align(data.traj[0], data.traj[1], x0, y0, px, py, cum, valid,
                                        p.trajectory_point_step)


@numba.njit(cache=True, fastmath=True)
def _align(x, y, x0, y0, px, py, cum, valid, step):
    """Per trajectory, the mean distance of its sampled points to the arc-length-matched path point."""
    b, t = x.shape
    n = cum.shape[0]
    out = np.zeros(b, np.float32)
    for k in range(b):
        s, j, total, count = 0.0, 0, 0.0, 0
        lx, ly = x0, y0
        for i in range(step - 1, t, step):
            dx, dy = x[k, i] - lx, y[k, i] - ly
            lx, ly = x[k, i], y[k, i]
            s += np.sqrt(dx * dx + dy * dy)
            while j + 1 < n and cum[j + 1] <= s:
                j += 1
            m = j + 1 if (j + 1 < n and cum[j + 1] - s < s - cum[j]) else j
            if valid[m]:
                ex, ey = x[k, i] - px[m], y[k, i] - py[m]
                total += np.sqrt(ex * ex + ey * ey)
                count += 1
        if count > 0:
            out[k] = total / count
    return out
