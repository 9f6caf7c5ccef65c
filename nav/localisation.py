"""Where the ``map -> odom`` transform comes from.

Navigation asks a ``Localisation`` for ``map -> odom`` and never looks at ground truth. This
robot's two live sources are SLAM (``nav.slam.supervisor``: scan matching, loop closure, in a
worker process) and AMCL on a saved map (``nav.amcl``); ``get_localisation`` picks one from
config. ``OdometryOnly`` is their stub twin: it holds ``map -> odom`` at identity, so the map
frame is the start pose (spec/mission.md: in SLAM mode too, the map origin is the dock) and
the map pose is wheel odometry; tests of navigation alone use it.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Optional, Protocol

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import PeopleSource, nobody
from nav.amcl.localisation import AmclLocalisation
from nav.map_io import load_map
from nav.occupancy import OccupancyMap
from nav.slam.supervisor import SlamSupervisor

if TYPE_CHECKING:
    from nav.config import NavConfig


class Localisation(Protocol):
    rate: float
    """Hz the runtime ticks it at."""

    def tick(self, now: float) -> None:
        """Take in what arrived since the last beat (scans, odometry)."""

    def close(self) -> None:
        """Release what it holds (SLAM's worker process)."""

    def map_to_odom(self) -> Pose2D:
        """The current ``map -> odom`` transform."""

    def ready(self) -> bool:
        """True once ``map -> odom`` resolves (the readiness cascade's last stage)."""

    def has_map(self) -> bool:
        """True once a map exists (the cascade's middle stage)."""


class OdometryOnly:
    """``map -> odom`` held at identity: the map frame is the start pose."""

    rate = 1.0

    def tick(self, now: float) -> None:
        pass

    def close(self) -> None:
        pass

    def map_to_odom(self) -> Pose2D:
        return Pose2D()

    def ready(self) -> bool:
        return True

    def has_map(self) -> bool:
        """No map to wait for: the map frame is the start pose."""
        return True


def get_localisation(cfg: "NavConfig", odom_pose: Callable[[], Pose2D], scan: Callable[[], Optional[LidarScan]],
                     on_map: Callable[[OccupancyMap], None], deterministic_clock: bool = True,
                     people: PeopleSource = nobody) -> Localisation:
    """What ``nav.slam`` selects (kiss-icp's ``get_<thing>(config)``: callers never branch):
    SLAM in its worker process, or AMCL on the saved map ``nav.map_file`` (loaded and checked
    here, so a bad map file is reported before the robot moves). ``people``: those whose returns
    SLAM neither registers nor maps (``nav.slam.people_mask``)."""
    mount = Pose2D(*cfg.navigator.lidar_mount)
    if cfg.slam:
        return SlamSupervisor(cfg.mapping, mount, odom_pose, scan, on_map, deterministic_clock, people)
    saved = load_map(cfg.map_file)
    on_map(saved)
    return AmclLocalisation(cfg.amcl, saved, mount, odom_pose, scan)
