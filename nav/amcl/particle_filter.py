"""The particle filter: Nav2's AMCL on a saved map, vectorised over a fixed-size cloud.

``update(odom_pose, scan)`` takes a scan and the wheel-odometry pose it was taken at:

1. motion: each particle moves by the odometry step since the last update through Nav2's
   OmniMotionModel (``motion_model``, the seed's alphas);
2. sensor: each particle's log weight gains the likelihood-field score (``likelihood_field``)
   of up to ``max_beams`` returns, spread evenly over the usable ones: returns below
   ``laser_min_range`` (the robot's own arm, seed), at or past ``laser_max_range`` and ``inf``
   (no return) are dropped before the choice, where Nav2 chooses among all beams and skips the
   unusable, so a sector the arm blocks does not thin the evidence;
3. resample: low-variance (systematic) resampling (Thrun et al., Probabilistic Robotics,
   table 4.4) every ``resample_interval`` updates, with Nav2's random-particle recovery when
   its alphas are set (off by default).

When to update (Nav2 updates on the first scan, then only after ``update_min_d`` of travel
or ``update_min_a`` of rotation): the same once the cloud has converged, but until then on
every scan, standing still included, with a little roughening after each resampling so the
cloud does not collapse onto a few particles. That is Nav2's ``request_nomotion_update``
service called each scan until the filter is sure, and it is what lets a robot parked
0.5 m / 0.3 rad off its configured pose localise before it moves. Converged means tight
(``converged_std``: one mode, not two pots apart) and still (``converged_drift``: not sliding
any more), and latches until ``initialise``: the filter then goes back to Nav2's gating and
does not return to updating on every scan while parked, since one scan repeated is not new
evidence. Everything random comes from one generator seeded from the config, so a run
repeats exactly.
"""
from __future__ import annotations

import math
from collections import deque
from typing import Optional

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D, wrap_angle, wrap_angles
from nav.amcl.config import AmclConfig
from nav.amcl.likelihood_field import LikelihoodField
from nav.amcl.motion_model import sample_motion
from nav.frames import compose, inverse
from nav.occupancy import OccupancyMap


class ParticleFilter:
    def __init__(self, config: AmclConfig, occupancy: OccupancyMap, lidar_mount: Pose2D):
        self.config = config
        self.map = occupancy
        self.field = LikelihoodField(occupancy, config.laser_likelihood_max_dist, config.z_hit, config.z_rand,
                                     config.sigma_hit, config.laser_max_range)
        self.mount = lidar_mount
        self.rng = np.random.default_rng(config.seed)
        self._free: Optional[np.ndarray] = None
        self.initialise(Pose2D(*config.initial_pose), config.initial_cov)

    # -- the interface -------------------------------------------------------------------------

    def initialise(self, pose: Pose2D, cov: tuple[float, float, float]) -> None:
        """A Gaussian cloud round ``pose`` (map frame) with variances ``cov`` (x m^2, y m^2, yaw
        rad^2): Nav2's initial pose, RViz's 2D Pose Estimate. Forgets the odometry and the
        convergence."""
        n = self.config.particles
        std = np.sqrt(np.asarray(cov, np.float64))
        self.particles = np.column_stack([pose.x + std[0] * self.rng.normal(size=n),
                                          pose.y + std[1] * self.rng.normal(size=n),
                                          wrap_angles(pose.yaw + std[2] * self.rng.normal(size=n))])
        self.log_weights = np.zeros(n)
        self.scans = 0
        """Scans integrated since ``initialise``."""
        self.converged = False
        """Latched once ``spread`` is under ``converged_std`` and the estimate holds still."""
        self._recent: deque[Pose2D] = deque(maxlen=self.config.converged_window + 1)
        self._odom: Optional[Pose2D] = None
        self._updates = 0
        self._w_slow = self._w_fast = 0.0

    def update(self, odom_pose: Pose2D, scan: LidarScan) -> bool:
        """Fold in ``scan``, taken at wheel-odometry pose ``odom_pose``; False when skipped (the
        cloud has converged and the robot has not moved enough since the last update)."""
        cfg = self.config
        if self._odom is not None:
            if self.converged and not self._moved(self._odom, odom_pose):
                return False
            sample_motion(self.particles, self._odom, odom_pose, cfg.alphas, self.rng)
        self._odom = odom_pose
        self._updates += 1
        angles, ranges = self.beams(scan)
        if len(ranges):
            self._sense(angles, ranges)
            if self._updates % cfg.resample_interval == 0:
                self._resample()
            self.scans += 1
            if not self.converged:
                self.converged = self._settled(odom_pose)
        return True

    def estimate(self) -> Pose2D:
        """``base_link`` in the map frame: the weighted mean of the cloud, yaw by circular mean."""
        w = self.weights()
        p = self.particles
        yaw = math.atan2(float(w @ np.sin(p[:, 2])), float(w @ np.cos(p[:, 2])))
        return Pose2D(float(w @ p[:, 0]), float(w @ p[:, 1]), yaw)

    def spread(self) -> tuple[float, float]:
        """(std_xy, std_yaw): the position std along the cloud's widest axis (the square root of
        its covariance's larger eigenvalue, m; in an aisle the along-aisle uncertainty is the
        one that matters) and the yaw std about the circular mean, rad."""
        w = self.weights()
        mean = self.estimate()
        dx, dy = self.particles[:, 0] - mean.x, self.particles[:, 1] - mean.y
        cov = np.array([[w @ (dx * dx), w @ (dx * dy)], [w @ (dx * dy), w @ (dy * dy)]])
        dyaw = wrap_angles(self.particles[:, 2] - mean.yaw)
        return math.sqrt(max(float(np.linalg.eigvalsh(cov)[-1]), 0.0)), math.sqrt(float(w @ (dyaw * dyaw)))

    def weights(self) -> np.ndarray:
        """(N,) normalised particle weights."""
        w = np.exp(self.log_weights - self.log_weights.max())
        return w / w.sum()

    # -- the pieces ----------------------------------------------------------------------------

    def _settled(self, odom_pose: Pose2D) -> bool:
        """Tight (``converged_std``) and still (``converged_drift`` over ``converged_window``).
        "Still" is judged on the correction, not the pose: each recent estimate is carried to
        now by the odometry since, so a robot driving while it converges is still by this
        test when the filter agrees with its wheels."""
        cfg = self.config
        now = self.estimate()
        self._recent.append(compose(now, inverse(odom_pose)))  # map -> odom at this update
        xy, yaw = self.spread()
        if len(self._recent) <= cfg.converged_window or xy >= cfg.converged_std[0] or yaw >= cfg.converged_std[1]:
            return False
        for map_to_odom in self._recent:
            then = compose(map_to_odom, odom_pose)
            if (math.hypot(now.x - then.x, now.y - then.y) >= cfg.converged_drift[0]
                    or abs(wrap_angle(now.yaw - then.yaw)) >= cfg.converged_drift[1]):
                return False
        return True

    def _moved(self, a: Pose2D, b: Pose2D) -> bool:
        """Nav2's update gate (its per-axis test made rotation-invariant: travel by distance)."""
        return (math.hypot(b.x - a.x, b.y - a.y) > self.config.update_min_d
                or abs(wrap_angle(b.yaw - a.yaw)) > self.config.update_min_a)

    def beams(self, scan: LidarScan) -> tuple[np.ndarray, np.ndarray]:
        """(angles, ranges) of up to ``max_beams`` usable returns, evenly spread, lidar frame."""
        cfg = self.config
        r = np.asarray(scan.ranges, np.float64)
        ok = np.flatnonzero(np.isfinite(r) & (r >= cfg.laser_min_range) & (r < cfg.laser_max_range))
        if len(ok) > cfg.max_beams:
            ok = ok[np.linspace(0, len(ok) - 1, cfg.max_beams).round().astype(np.int64)]
        return np.asarray(scan.angles, np.float64)[ok], r[ok]

    def endpoints(self, angles: np.ndarray, ranges: np.ndarray) -> np.ndarray:
        """(P, B, 2) map-frame beam endpoints of every particle (particle * lidar mount * beam)."""
        p, m = self.particles, self.mount
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        lx = p[:, 0] + c * m.x - s * m.y
        ly = p[:, 1] + s * m.x + c * m.y
        a = (p[:, 2] + m.yaw)[:, None] + angles[None, :]
        return np.stack([lx[:, None] + ranges * np.cos(a), ly[:, None] + ranges * np.sin(a)], axis=-1)

    def _sense(self, angles: np.ndarray, ranges: np.ndarray) -> None:
        score = self.field.score(self.endpoints(angles, ranges))
        if self.config.recovery_alpha_slow > 0 or self.config.recovery_alpha_fast > 0:
            w_avg = float(self.weights() @ np.exp(score))  # Nav2's mean measurement likelihood
            if self._w_slow == 0.0:
                self._w_slow = self._w_fast = w_avg
            else:
                self._w_slow += self.config.recovery_alpha_slow * (w_avg - self._w_slow)
                self._w_fast += self.config.recovery_alpha_fast * (w_avg - self._w_fast)
        self.log_weights = self.log_weights + score
        self.log_weights -= self.log_weights.max()

    def _resample(self) -> None:
        """Low-variance resampling; with recovery on, a share ``1 - w_fast / w_slow`` of the new
        cloud is drawn uniformly over the map's free cells instead (Nav2's recovery)."""
        n = len(self.particles)
        cum = np.cumsum(self.weights())
        idx = np.minimum(np.searchsorted(cum, (self.rng.random() + np.arange(n)) / n, side="right"), n - 1)
        self.particles = self.particles[idx]
        self.log_weights = np.zeros(n)
        w_diff = 1.0 - self._w_fast / self._w_slow if self._w_slow > 0 else 0.0
        if w_diff > 0:
            fresh = self.rng.random(n) < w_diff
            self.particles[fresh] = self._random_poses(int(fresh.sum()))
            self._w_slow = self._w_fast = 0.0
        if not self.converged:
            self.particles += self.rng.normal(size=self.particles.shape) * self.config.roughening
            self.particles[:, 2] = wrap_angles(self.particles[:, 2])

    def _random_poses(self, k: int) -> np.ndarray:
        """``k`` poses uniform over the map's free cells, any heading (Nav2's uniform pose)."""
        if self._free is None:
            occ = self.map.occupancy
            self._free = np.flatnonzero((occ >= 0) & (occ <= 25))  # map_server's free_thresh 0.25
        if len(self._free) == 0:
            return self.particles[:k].copy()
        cell = self._free[self.rng.integers(0, len(self._free), k)]
        x, y = self.map.geometry.centre_of(cell % self.map.width, cell // self.map.width)
        jitter = (self.rng.random((k, 2)) - 0.5) * self.map.resolution
        return np.column_stack([x + jitter[:, 0], y + jitter[:, 1], self.rng.uniform(-math.pi, math.pi, k)])
