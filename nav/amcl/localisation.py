"""AMCL behind the ``Localisation`` interface: ``map -> odom`` from a saved map.

``tick`` (10 Hz, the lidar's rate, scheduled by the navigation runtime) hands the filter each
new scan with the wheel-odometry pose read at the same tick, standing in for the pose at the
scan's stamp (the newest scan is at most one lidar period old). After every filter update
``map -> odom`` becomes the estimate composed with the inverse of that odometry pose, which
is what Nav2's amcl broadcasts; between updates it is held, so the robot's map pose
(``map -> odom`` * odometry) follows odometry smoothly and jumps only when the filter
corrects it (REP-105). Before the first update it is the configured initial pose composed the
same way.

The map is there from the start (it was loaded), so ``has_map`` is always true; ``ready`` is
true once the filter has integrated a scan and its cloud has converged, which is what the
readiness cascade waits for: navigation does not start on a guess. It stays true after that
(the filter's convergence latches) until ``reset``. A scan too blind to trust (``AmclConfig.blind``)
is not fed to the filter: ``map -> odom`` is held, and the pose follows odometry through it.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.scan_trust import ScanTrust
from nav.amcl.config import AmclConfig
from nav.amcl.particle_filter import ParticleFilter
from nav.frames import compose, inverse
from nav.occupancy import OccupancyMap


class AmclLocalisation:
    rate = 10.0
    """Hz the runtime schedules ``tick`` at: the lidar's revolution rate."""

    def __init__(self, config: AmclConfig, occupancy: OccupancyMap, lidar_mount: Pose2D,
                 odom_pose: Callable[[], Pose2D], scan: Callable[[], Optional[LidarScan]]):
        self.config = config
        self.occupancy = occupancy
        self.filter = ParticleFilter(config, occupancy, lidar_mount)
        self.odom_pose, self.scan = odom_pose, scan
        self.trust = ScanTrust(config.blind)
        self._stamp: Optional[float] = None
        self._map_to_odom = compose(Pose2D(*config.initial_pose), inverse(odom_pose()))

    def map_to_odom(self) -> Pose2D:
        return self._map_to_odom

    def close(self) -> None:
        """Nothing to release: the filter lives in this process."""

    def has_map(self) -> bool:
        return True

    def ready(self) -> bool:
        return self.filter.scans > 0 and self.filter.converged

    def tick(self, now: float) -> None:
        """Feed the filter the newest scan, once per scan; re-derive ``map -> odom`` if it updated."""
        scan = self.scan()
        if scan is None or (self._stamp is not None and scan.stamp <= self._stamp):
            return
        self._stamp = scan.stamp
        if self.trust.judge(scan.angles, np.isfinite(scan.ranges)) is not None:
            return
        odom = self.odom_pose()
        if self.filter.update(odom, scan):
            self._map_to_odom = compose(self.filter.estimate(), inverse(odom))

    def reset(self, pose: Pose2D, cov: Optional[tuple[float, float, float]] = None) -> None:
        """Reseed the cloud at ``pose`` in the map frame (RViz's 2D Pose Estimate), with the
        configured initial covariance unless given; not ready until it converges again."""
        self.filter.initialise(pose, cov or self.config.initial_cov)
        self._map_to_odom = compose(pose, inverse(self.odom_pose()))
