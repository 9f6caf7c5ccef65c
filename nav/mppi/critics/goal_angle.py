"""GoalAngleCritic (seed weight 3.0): within 0.5 m of the goal, the mean absolute heading error
of every trajectory point to the goal's yaw: it squares the robot up for the tight 0.12 rad
tolerance that frames the tag."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData, shortest_angle
from nav.mppi.critics.base import Critic


class GoalAngleCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance > p.threshold_to_consider:
            return
        err = np.abs(shortest_angle(data.traj[2], data.goal[2]))
        data.costs += p.weight * err.mean(axis=1)
