"""PathFollowCritic (seed weight 5.0): distance from each trajectory's end to the path point
``offset_from_furthest`` (6) past the furthest one reached: progress along the path, not just
parallel to it. Off within 1.4 m of the goal, where the goal critics take over."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class PathFollowCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance <= p.threshold_to_consider or len(data.path) < 2:
            return
        i = min(data.furthest_reached + p.offset_from_furthest, len(data.path) - 1)
        tx, ty = data.path[i, 0], data.path[i, 1]
        data.costs += p.weight * np.hypot(data.traj[0, :, -1] - tx, data.traj[1, :, -1] - ty)
