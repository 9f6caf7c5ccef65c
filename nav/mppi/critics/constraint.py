"""ConstraintCritic (seed weight 4.0): velocity-envelope violations integrated over time.

The rollout already clamps each axis to its limits, so what is left to penalise is Nav2's omni
rule: the *combined* translational speed, signed by vx, must stay inside [vx_min, vx_max], so a
diagonal of vx 0.5 and vy 0.5 (0.71 m/s) is not free."""
from __future__ import annotations

import numba
import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.mppi.critic_data import CriticData
from nav.mppi.critics.base import Critic


class ConstraintCritic(Critic):
    def __init__(self, params, costmaps: CostmapsConfig, vx_min: float, vx_max: float):
        super().__init__(params, costmaps)
        self.vx_min, self.vx_max = vx_min, vx_max

    def score(self, data: CriticData) -> None:
        data.costs += self.params.weight * _violation(data.v[0], data.v[1], self.vx_min, self.vx_max) * data.dt


@numba.njit(cache=True, fastmath=True)
def _violation(vx, vy, lo, hi):
    """Per trajectory, the sum over time of how far sign(vx) * |(vx, vy)| leaves [lo, hi]."""
    b, t = vx.shape
    out = np.zeros(b, np.float32)
    for k in range(b):
        acc = 0.0
        for i in range(t):
            s = np.sqrt(vx[k, i] * vx[k, i] + vy[k, i] * vy[k, i])
            if vx[k, i] < 0.0:
                s = -s
            if s > hi:
                acc += s - hi
            elif s < lo:
                acc += lo - s
        out[k] = acc
    return out
