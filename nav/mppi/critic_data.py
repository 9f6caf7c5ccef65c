"""Everything a critic may read, in one object (Nav2's CriticData), and the path helpers the
critics share."""
from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

from nav.costmap.grid import CostGrid


@dataclass
class CriticData:
    pose: np.ndarray  # (3,) x, y, yaw of the robot, costmap frame
    v: np.ndarray  # (3, B, T) vx, vy, wz per trajectory step (after the envelope)
    traj: np.ndarray  # (3, B, T) x, y, yaw per step
    path: np.ndarray  # (N, 3) x, y, yaw, pruned plan from the robot on
    goal: np.ndarray  # (3,) x, y, yaw
    grid: CostGrid
    dt: float
    costs: np.ndarray  # (B,) float32, the critics add into it
    fail: bool = False
    """Set by the obstacles critic when every trajectory collides."""
    _furthest: int | None = field(default=None, repr=False)

    @property
    def goal_distance(self) -> float:
        """Distance from the robot to the goal (critics switch on or off with it)."""
        return float(np.hypot(self.goal[0] - self.pose[0], self.goal[1] - self.pose[1]))

    @property
    def furthest_reached(self) -> int:
        """Index of the furthest path point any trajectory's end comes nearest to (Nav2's
        findPathFurthestReachedPoint), computed once per cycle for every critic."""
        if self._furthest is None:
            ex, ey = self.traj[0, :, -1], self.traj[1, :, -1]
            px, py = self.path[:, 0].astype(np.float32), self.path[:, 1].astype(np.float32)
            d = (ex[:, None] - px[None, :]) ** 2 + (ey[:, None] - py[None, :]) ** 2
            self._furthest = int(np.argmin(d, axis=1).max())
        return self._furthest


def shortest_angle(a, b):
    """Signed a - b wrapped to [-pi, pi] (rint is several times cheaper than remainder)."""
    d = np.subtract(a, b, dtype=np.float32)
    return d - np.float32(2 * np.pi) * np.rint(d * np.float32(1 / (2 * np.pi)))


@numba.njit(cache=True, fastmath=True)
def mean_abs_angle_error(yaw, target):
    """Per trajectory, the mean over time of |yaw - target| wrapped: (B, T) -> (B,)."""
    b, t = yaw.shape
    out = np.empty(b, np.float32)
    two_pi = 2.0 * np.pi
    for k in range(b):
        acc = 0.0
        for i in range(t):
            d = yaw[k, i] - target
            d -= two_pi * np.floor(d / two_pi + 0.5)
            acc += abs(d)
        out[k] = acc / t
    return out
