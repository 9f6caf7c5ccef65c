"""GoalAngleCritic (seed weight 3.0): within 0.5 m of the goal, the mean absolute heading error
of every trajectory point to the goal's yaw: it squares the robot up for the tight 0.12 rad
tolerance that frames the tag."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData, mean_abs_angle_error
from nav.mppi.critics.base import Critic


class GoalAngleCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance > p.threshold_to_consider:
            return
        data.costs += p.weight * mean_abs_angle_error(data.traj[2], np.float32(data.goal[2]))
