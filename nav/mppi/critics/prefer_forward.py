"""PreferForwardCritic (seed weight 1.0, down from the diff-drive default 5.0): the time spent
reversing, sum of max(-vx, 0) * dt. Weak on purpose, so a cleanly shorter sideways approach is
not overridden; off within 0.5 m of the goal."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class PreferForwardCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance <= p.threshold_to_consider:
            return
        data.costs += p.weight * np.maximum(-data.v[0], 0.0).sum(axis=1) * data.dt
