"""GoalCritic (seed weight 5.0): once within ``threshold_to_consider`` (1.4 m) of the goal, the
mean distance of every trajectory point to the goal position."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class GoalCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance > p.threshold_to_consider:
            return
        d = np.hypot(data.traj[0] - data.goal[0], data.traj[1] - data.goal[1])
        data.costs += p.weight * d.mean(axis=1)
