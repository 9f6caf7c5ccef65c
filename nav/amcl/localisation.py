"""AMCL behind the ``Localisation`` interface: ``map -> odom`` from a saved map.

``tick`` (10 Hz, the lidar's rate) feeds the filter the newest scan with the wheel odometry
pose it was taken at. ``map -> odom`` is the filter's estimate composed with the inverse of
that odometry pose; it changes only when the filter updates, so between updates the robot's
map pose follows odometry smoothly (REP-105). The map exists from the start (it was loaded);
the transform resolves once the cloud has converged, which is what the readiness cascade waits
for: navigation does not start on a guess.
"""
from __future__ import annotations

from typing import Callable, Optional

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from nav.amcl.config import AmclConfig
from nav.amcl.particle_filter import ParticleFilter
from nav.frames import compose, inverse
from nav.occupancy import OccupancyMap


class AmclLocalisation:
    rate = 10.0

    def __init__(self, cfg: AmclConfig, occupancy: OccupancyMap, lidar_mount: Pose2D,
                 odom_pose: Callable[[], Pose2D], scan: Callable[[], Optional[LidarScan]]):
        self.filter = ParticleFilter(cfg, occupancy, lidar_mount)
        self.occupancy = occupancy
        self.odom_pose, self.scan = odom_pose, scan
        self._map_to_odom = compose(Pose2D(*cfg.initial_pose), inverse(odom_pose()))
        self._stamp = -1.0

    def map_to_odom(self) -> Pose2D:
        return self._map_to_odom

    def has_map(self) -> bool:
        return True

    def ready(self) -> bool:
        return self.filter.settled

    def tick(self, now: float) -> None:
        scan = self.scan()
        if scan is None or scan.stamp <= self._stamp:
            return
        self._stamp = scan.stamp
        odom = self.odom_pose()
        if self.filter.update(odom, scan):
            self._map_to_odom = compose(self.filter.estimate(), inverse(odom))

    def reset(self, pose: Pose2D, std=None) -> None:
        """Reseed the cloud at ``pose`` (the map frame), as RViz's 2D Pose Estimate did."""
        self.filter.initialise(pose, std or self.filter.cfg.initial_std)
        self._map_to_odom = compose(pose, inverse(self.odom_pose()))
