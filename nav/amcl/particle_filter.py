"""The particle filter: Nav2's AMCL on a saved map, vectorised over a fixed cloud.

``update`` takes a scan and the wheel odometry pose it was taken at:

1. motion: every particle moves by the odometry step since the last update, perturbed by the
   Omni motion model (``motion_model``);
2. sensor: each particle is weighted by ``max_beams`` of the scan's returns through the
   likelihood field (``likelihood_field``), returns below 0.25 m and at max range dropped;
3. resample: low-variance (systematic) resampling, every update (Nav2's resample_interval 1).

Once it has converged (``settled``) it updates only after ``update_min_d`` / ``update_min_a``
of motion, as Nav2; before that it updates on every scan, standing still included, roughening
the resampled cloud a little, so a robot placed with a wrong initial pose localises before it
moves.
"""
from __future__ import annotations

import math

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from nav.amcl.config import AmclConfig
from nav.amcl.likelihood_field import LikelihoodField
from nav.amcl.motion_model import sample_motion
from nav.frames import distance, yaw_error
from nav.occupancy import OccupancyMap


class ParticleFilter:
    def __init__(self, cfg: AmclConfig, occupancy: OccupancyMap, lidar_mount: Pose2D):
        self.cfg = cfg
        self.field = LikelihoodField(occupancy, cfg.likelihood_max_dist, cfg.z_hit, cfg.z_rand, cfg.sigma_hit,
                                     cfg.laser_max_range)
        self.mount = lidar_mount
        self.rng = np.random.default_rng(cfg.seed)
        self.particles = np.zeros((cfg.particles, 3))
        self.weights = np.full(cfg.particles, 1.0 / cfg.particles)
        self._odom: Pose2D | None = None
        self.updates = 0
        self.initialise(Pose2D(*cfg.initial_pose), cfg.initial_std)

    def initialise(self, pose: Pose2D, std) -> None:
        """A Gaussian cloud round ``pose`` (Nav2's initial pose / RViz's 2D Pose Estimate)."""
        n = self.cfg.particles
        self.particles = np.column_stack([self.rng.normal(pose.x, std[0], n), self.rng.normal(pose.y, std[1], n),
                                          self.rng.normal(pose.yaw, std[2], n)])
        self.weights = np.full(n, 1.0 / n)
        self._odom = None
        self.updates = 0
        self.settled = False
        """Latched at the first convergence: from then on the filter updates only on motion
        (Nav2's gating) and the transform counts as resolved, whatever the cloud does after a
        motion update spreads it (alphas 0.2 spread a 0.25 m step by ~0.1 m)."""

    def converged(self) -> bool:
        pos, yaw = self.spread()
        return self.updates > 0 and pos < self.cfg.converged_std[0] and yaw < self.cfg.converged_std[1]

    def update(self, odom: Pose2D, scan: LidarScan) -> bool:
        """Fold one scan in; False when skipped (not moved enough since the last update)."""
        cfg = self.cfg
        if self._odom is not None and self.settled and \
                distance(self._odom, odom) < cfg.update_min_d and yaw_error(self._odom, odom) < cfg.update_min_a:
            return False
        if self._odom is not None:
            sample_motion(self.particles, self._odom, odom, cfg.alphas, self.rng)
        self._odom = odom
        beams = self._beams(scan)
        if len(beams[0]):
            w = self.field.weights(self._endpoints(*beams))
            self.weights = w / w.sum()
            self._resample()
            if not self.settled:
                self.particles += self.rng.normal(0.0, 1.0, self.particles.shape) * cfg.settle_jitter
        self.updates += 1
        self.settled = self.settled or self.converged()
        return True

    def estimate(self) -> Pose2D:
        """The weighted mean pose of ``base_link`` in ``map`` (circular mean for yaw)."""
        w = self.weights
        x, y = float(w @ self.particles[:, 0]), float(w @ self.particles[:, 1])
        yaw = math.atan2(float(w @ np.sin(self.particles[:, 2])), float(w @ np.cos(self.particles[:, 2])))
        return Pose2D(x, y, yaw)

    def spread(self) -> tuple[float, float]:
        """(position std m, yaw std rad) of the cloud."""
        w = self.weights
        mean = self.estimate()
        pos = math.sqrt(float(w @ ((self.particles[:, 0] - mean.x) ** 2 + (self.particles[:, 1] - mean.y) ** 2)) / 2)
        dyaw = np.remainder(self.particles[:, 2] - mean.yaw + math.pi, 2 * math.pi) - math.pi
        return pos, math.sqrt(float(w @ dyaw ** 2))

    # -- the pieces ----------------------------------------------------------------------------

    def _beams(self, scan: LidarScan) -> tuple[np.ndarray, np.ndarray]:
        """Up to ``max_beams`` usable returns, evenly spread over the revolution."""
        r = scan.ranges.astype(np.float64)
        ok = np.flatnonzero(np.isfinite(r) & (r >= self.cfg.laser_min_range) & (r < self.cfg.laser_max_range))
        if len(ok) > self.cfg.max_beams:
            ok = ok[np.linspace(0, len(ok) - 1, self.cfg.max_beams).round().astype(int)]
        return scan.angles[ok].astype(np.float64), r[ok]

    def _endpoints(self, angles: np.ndarray, ranges: np.ndarray) -> np.ndarray:
        """(P, B, 2) map-frame beam endpoints for every particle."""
        p = self.particles
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        lx = p[:, 0] + c * self.mount.x - s * self.mount.y
        ly = p[:, 1] + s * self.mount.x + c * self.mount.y
        a = p[:, 2:3] + self.mount.yaw + angles[None, :]
        return np.stack([lx[:, None] + ranges * np.cos(a), ly[:, None] + ranges * np.sin(a)], axis=-1)

    def _resample(self) -> None:
        """Low-variance resampling (Thrun et al., Probabilistic Robotics, table 4.4)."""
        n = len(self.weights)
        positions = (self.rng.random() + np.arange(n)) / n
        idx = np.minimum(np.searchsorted(np.cumsum(self.weights), positions), n - 1)
        self.particles = self.particles[idx]
        self.weights = np.full(n, 1.0 / n)
