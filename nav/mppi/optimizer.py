"""The MPPI optimizer: one control cycle as Nav2 runs it (../shared/reference/mppi.md).

1. noise: zero-mean normal per axis (vx_std, vy_std, wz_std), drawn once from a seeded generator
   and reused every cycle unless ``regenerate_noises`` (Nav2's default, and what keeps a run a
   pure function of its seed);
2. sampled controls ``cv = u + noise``; 3-4. the motion model rolls them out
   (``nav.mppi.motion_models``); 5. the critics add to one cost per trajectory;
6. control cost ``gamma / std^2 * sum_t u_t * noise_t`` per axis;
7. softmax weights ``exp(-(S - min S) / temperature)``, new ``u = sum_k w_k cv_k``;
8. Savitzky-Golay smoothing against the command history, velocity and acceleration limits;
9. the first element is the command; the sequence shifts left by one for the next cycle (the
   controller period equals model_dt, 0.05 s);
10. when every trajectory collides, reset and retry up to ``retry_attempt_limit`` times, then
    raise ``NoValidControl``.
"""
from __future__ import annotations

import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import CostGrid
from nav.mppi.config import MppiConfig
from nav.mppi.critic_data import CriticData
from nav.mppi.critics import make_critics
from nav.mppi.motion_models import motion_model
from nav.mppi.smoothing import HISTORY, enforce_limits, savitzky_golay


class NoValidControl(RuntimeError):
    """Every sampled trajectory collides, even after the retries."""


class Optimizer:
    def __init__(self, config: MppiConfig, costmaps: CostmapsConfig):
        self.config = config
        self.model = motion_model(config)
        self.critics = make_critics(config, costmaps)
        b, t = config.batch_size, config.time_steps
        self._std = np.array([config.vx_std, config.vy_std if self.model.holonomic else 0.0, config.wz_std],
                             dtype=np.float32)
        self._rng = np.random.default_rng(config.seed)
        self._noise = self._draw()
        self._v = np.empty((3, b, t), dtype=np.float32)
        self._traj = np.empty((3, b, t), dtype=np.float32)
        self.costs = np.zeros(b, dtype=np.float32)
        self.reset()

    def _draw(self) -> np.ndarray:
        c = self.config
        return (self._rng.standard_normal((3, c.batch_size, c.time_steps), dtype=np.float32)
                * self._std[:, None, None])

    def reset(self) -> None:
        """Forget the warm start (new goal, cancel, recovery, or all trajectories colliding)."""
        self.u = np.zeros((self.config.time_steps, 3), dtype=np.float32)
        self.history = np.zeros((HISTORY, 3), dtype=np.float32)
        self.applied = self.u

    @property
    def trajectories(self) -> np.ndarray:
        """The last cycle's sampled trajectories, (3, B, T) x, y, yaw."""
        return self._traj

    def rollout_sequence(self, u: np.ndarray, pose, velocity) -> np.ndarray:
        """A (T, 3) control sequence rolled out from ``pose`` and ``velocity``: (T, 3) x, y, yaw."""
        t = self.config.time_steps
        v, traj = np.empty((3, 1, t), np.float32), np.empty((3, 1, t), np.float32)
        self.model.rollout(np.ascontiguousarray(u.T[:, None, :], dtype=np.float32),
                           np.asarray(velocity, np.float32), pose, v, traj)
        return traj[:, 0, :].T.copy()

    def cycle(self, pose, velocity, path: np.ndarray, goal, grid: CostGrid) -> np.ndarray:
        """One control cycle; returns the (vx, vy, wz) command."""
        c = self.config
        v0 = np.asarray(velocity, dtype=np.float32)
        for attempt in range(c.retry_attempt_limit + 1):
            fail = False
            for _ in range(c.iteration_count):
                fail = self._iterate(pose, v0, path, goal, grid)
                if fail:
                    break
            if not fail:
                break
            self.reset()
        else:
            raise NoValidControl(f"every one of {c.batch_size} trajectories collides")
        u = savitzky_golay(self.u, self.history)
        u = enforce_limits(u, self.model.lo, self.model.hi, self.model.acc, c.model_dt, v0)
        command = u[0].copy()
        self.applied = u  # the sequence the command came from, before the shift (for drawing)
        self.history = np.vstack([self.history[1:], command])
        self.u = np.vstack([u[1:], u[-1:]])
        if c.regenerate_noises:
            self._noise = self._draw()
        return command

    def _iterate(self, pose, v0, path, goal, grid) -> bool:
        c = self.config
        cv = self.u.T[:, None, :] + self._noise
        self.model.rollout(cv, v0, pose, self._v, self._traj)
        self.costs[:] = 0.0
        data = CriticData(np.asarray(pose, np.float32), self._v, self._traj, path, np.asarray(goal, np.float32),
                          grid, c.model_dt, self.costs)
        for critic in self.critics:
            critic.score(data)
        if data.fail:
            return True
        for a in range(3):
            if self._std[a] > 0:
                self.costs += (c.gamma / self._std[a] ** 2) * (self._noise[a] @ self.u[:, a])
        s = self.costs - self.costs.min()
        w = np.exp(-s / np.float32(c.temperature))
        w /= w.sum()
        self.u = np.stack([w @ cv[a] for a in range(3)], axis=1).astype(np.float32)
        return False
