"""The simulated RPLidar C1: ~500 rays per revolution at 10 Hz with ``mj_multiRay``.

A revolution is produced per 1/rate of sim time. It is cast lazily, when someone asks for
the latest scan, from the pose at that moment (the scan is not smeared over the rotation; at
the base's speeds that is well under the range noise). Noise for revolution k is drawn from a
generator seeded by (seed, k), so what a run sees does not depend on who asked when.

Rays see world collision geoms (group 0) and the robots' geoms (group 1), all but the lidar's own
body, so, as in the original sim, the lidar sees the robot's arm; consumers filter returns below
0.25 m (seed). In a fleet it sees the other robots the same way, as what stands in its 0.21 m
plane: their arms and lidar pucks (their chassis top out at 0.135 m, below it).
Returns outside [range_min, range_max] are ``inf`` (the C1 reports 0 = no return).
"""
from __future__ import annotations

import math

import mujoco
import numpy as np

from hw.interfaces import LidarScan
from sim.config import LidarConfig
from sim.engine import Engine

GEOM_GROUPS = np.array([1, 1, 0, 0, 0, 0], dtype=np.uint8)


class SimLidar:
    def __init__(self, engine: Engine, config: LidarConfig):
        self.engine = engine
        self.config = config
        self._site = engine.id(mujoco.mjtObj.mjOBJ_SITE, "lidar_site")
        self._body = engine.id(mujoco.mjtObj.mjOBJ_BODY, "lidar")
        n = config.points
        self.angles = (np.arange(n) * (2 * math.pi / n)).astype(np.float32)
        self._local = np.stack([np.cos(self.angles), np.sin(self.angles), np.zeros(n)], axis=1).astype(np.float64)
        self._geomid = np.zeros(n, dtype=np.int32)
        self._dist = np.zeros(n, dtype=np.float64)
        self._cache: tuple[int, LidarScan] | None = None
        self.dropout_until = -1.0
        self.blind_until = -1.0
        """Until then every revolution arrives on time with no valid return (covered, sun)."""

    def cast(self) -> np.ndarray:
        """One noiseless revolution from the current pose: metres, ``inf`` where nothing hit."""
        d = self.engine.data
        pnt = d.site_xpos[self._site].copy()
        rot = d.site_xmat[self._site].reshape(3, 3)
        vec = (self._local @ rot.T).ravel()
        with self.engine.spending():
            mujoco.mj_multiRay(self.engine.model, d, pnt, vec, GEOM_GROUPS, 1, self._body,
                               self._geomid, self._dist, None, self.config.points, self.config.range_max)
        r = self._dist.copy()
        r[self._geomid < 0] = np.inf
        return r

    def latest_scan(self) -> LidarScan | None:
        t = self.engine.time
        if t < self.dropout_until:
            return None
        k = int(math.floor(t * self.config.rate + 1e-9))
        if self._cache is not None and self._cache[0] == k:
            return self._cache[1]
        ranges = self.cast()
        rng = np.random.default_rng([self.engine.config.seed, 1, k])
        ranges = ranges + rng.normal(0.0, self.config.noise_std, ranges.shape)
        ranges[(ranges < self.config.range_min) | (ranges > self.config.range_max)] = np.inf
        if t < self.blind_until:
            ranges[:] = np.inf
        scan = LidarScan(k / self.config.rate, self.angles, ranges.astype(np.float32))
        self._cache = (k, scan)
        return scan
