"""ConstraintCritic (seed weight 4.0): velocity-envelope violations integrated over time.

The rollout already clamps each axis to its limits, so what is left to penalise is Nav2's omni
rule: the *combined* translational speed, signed by vx, must stay inside [vx_min, vx_max], so a
diagonal of vx 0.5 and vy 0.5 (0.71 m/s) is not free."""
from __future__ import annotations

import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class ConstraintCritic(Critic):
    def __init__(self, params, costmaps: CostmapsConfig, vx_min: float, vx_max: float):
        super().__init__(params, costmaps)
        self.vx_min, self.vx_max = vx_min, vx_max

    def score(self, data: CriticData) -> None:
        vx, vy = data.v[0], data.v[1]
        speed = np.where(vx >= 0.0, 1.0, -1.0) * np.hypot(vx, vy)
        over = np.maximum(speed - self.vx_max, 0.0) + np.maximum(self.vx_min - speed, 0.0)
        data.costs += self.params.weight * over.sum(axis=1) * data.dt
