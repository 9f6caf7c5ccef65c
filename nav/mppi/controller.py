"""The MPPI controller as the navigator calls it at 20 Hz.

``compute(pose, velocity, path, goal, grid)`` takes the robot's pose and measured body velocity,
the plan pruned to the local window (with headings), the goal and the local costmap, all in one
frame (``odom``), and returns the body-frame command. Two things happen here rather than in the
optimizer:

- measured lateral speeds below ``min_y_velocity_threshold`` (0.001) read as zero (the seed:
  "so lateral motion is never gated as noise"; the diff-drive default 0.5 would hide strafes);
- for a holonomic model the plan's orientations become the goal's heading: the base does not
  need to face where it drives, so PathAngle (``path_orientation`` mode) asks it to hold the
  heading it must arrive with, and the final squaring-up for the 0.12 rad tolerance starts
  early instead of fighting the plan's tangent at the end. A diff-drive model keeps tangents.

After each ``compute``, ``optimal_trajectory`` (T, 3) is the smoothed control sequence rolled
out from the pose (what the robot intends to do, Nav2's published optimal trajectory) and
``sampled_trajectories`` (SAMPLES, T, 3) is an evenly spaced handful of the batch, for drawing.
"""
from __future__ import annotations

import numpy as np

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import CostGrid
from nav.mppi.config import MppiConfig
from nav.mppi.optimizer import NoValidControl, Optimizer

__all__ = ["MppiController", "NoValidControl"]


SAMPLES = 16
"""Sampled trajectories kept for drawing."""


class MppiController:
    def __init__(self, config: MppiConfig, costmaps: CostmapsConfig):
        self.config = config
        self.optimizer = Optimizer(config, costmaps)
        self.optimal_trajectory: np.ndarray | None = None
        self.sampled_trajectories: np.ndarray | None = None

    def reset(self) -> None:
        """Forget the warm-started control sequence (new goal, cancel, recovery)."""
        self.optimizer.reset()
        self.optimal_trajectory = self.sampled_trajectories = None

    def compute(self, pose, velocity, path: np.ndarray, goal, grid: CostGrid) -> tuple[float, float, float]:
        vx, vy, wz = velocity
        if abs(vy) < self.config.min_y_velocity_threshold or not self.optimizer.model.holonomic:
            vy = 0.0
        path = np.array(path, dtype=np.float64)
        if self.optimizer.model.holonomic:
            path[:, 2] = goal[2]
        pose = tuple(float(p) for p in pose)
        opt = self.optimizer
        try:
            cmd = opt.cycle(pose, (vx, vy, wz), path, goal, grid)
        except NoValidControl:
            self.optimal_trajectory = self.sampled_trajectories = None
            raise
        self.optimal_trajectory = opt.rollout_sequence(opt.applied, pose, (vx, vy, wz))
        every = max(1, self.config.batch_size // SAMPLES)
        self.sampled_trajectories = opt.trajectories[:, ::every][:, :SAMPLES].transpose(1, 2, 0).copy()
        return float(cmd[0]), float(cmd[1]), float(cmd[2])
