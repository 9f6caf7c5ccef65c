"""What localisation matches: the lidar's revolution less the returns on people.

SLAM and AMCL both assume the world they match a scan against stands still. A walker does not,
and near the robot a walker fills the view: a cart pusher coming head-on down a 0.9 m aisle at a
robot standing still moved SLAM's estimate 0.55 m towards them in 1.5 s (the cart's face closing
in read as the robot closing on a wall; along an aisle the rows give little else to hold on to),
and a cart pushed over the robot turned its heading 8 deg (held-out seed 4 of ``safety.people``:
the map drawn from then on was wrong, and the patrol lost 26 pots). So the returns within a
tracked person's body (their radius and ``MARGIN``) are taken out of the scan localisation sees,
as dropped returns (``inf``), before it is registered, mapped or weighed. A scan left with too few
returns to trust (people filling the view, or a cart over the lidar) is then blind to the
localisation's own ``hw.scan_trust`` rule, and the pose goes on by wheel odometry through it.

Side effect, wanted: a worker who stands still is no longer drawn into the SLAM map.
People come in ``odom`` (``hw.people``), the scan in the lidar frame; ``lidar`` is the lidar's
odom pose when the scan is read (the tracker works on the same newest scan).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Optional

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import PeopleSource

MARGIN = 0.15
"""Beyond a person's tracked radius, m: a scan's walk at 1.5 m/s (the tracker's people are a
revolution old when localisation reads the next) and a cart's corner off its circle."""


def without_people(scan: LidarScan, people, lidar: Pose2D, margin: float = MARGIN) -> LidarScan:
    """``scan`` with every return within a person's radius + ``margin`` made ``inf``; the same
    scan with nobody about."""
    if not people:
        return scan
    r = np.asarray(scan.ranges, dtype=np.float64)
    a = np.asarray(scan.angles, dtype=np.float64) + lidar.yaw
    x, y = lidar.x + r * np.cos(a), lidar.y + r * np.sin(a)
    hit = np.zeros(len(r), bool)
    for p in people:
        hit |= np.hypot(x - p.x, y - p.y) <= p.radius + margin
    if not hit.any():
        return scan
    return replace(scan, ranges=np.where(hit, np.inf, scan.ranges).astype(scan.ranges.dtype))


def static_scan(scan: Callable[[], Optional[LidarScan]], people: PeopleSource,
                lidar: Callable[[], Pose2D]) -> Callable[[], Optional[LidarScan]]:
    """The scan source localisation reads: ``scan``'s newest revolution less the people."""

    def read() -> Optional[LidarScan]:
        s = scan()
        return None if s is None else without_people(s, people(), lidar())

    return read
