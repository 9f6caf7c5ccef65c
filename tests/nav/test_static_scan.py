"""The scan localisation matches: the lidar's returns less those on tracked people."""
from __future__ import annotations

import math

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import Person
from nav.static_scan import MARGIN, static_scan, without_people


def ring(radius: float = 2.0, beams: int = 360) -> LidarScan:
    """A revolution inside a round wall ``radius`` off."""
    angles = np.linspace(-math.pi, math.pi, beams, endpoint=False).astype(np.float32)
    return LidarScan(1.0, angles, np.full(beams, radius, np.float32))


def test_returns_on_a_person_are_dropped_and_the_rest_kept():
    scan = ring()
    lidar = Pose2D(1.0, 0.0, math.pi / 2)  # odom: the lidar at (1, 0), facing +y
    person = Person(1, 1.0, 1.0, 0.0, 0.0, 0.25, 1.0)  # 1 m ahead of it, where no return lands
    wall = Person(2, 1.0, 2.0, 0.0, 0.0, 0.25, 1.0)  # on the wall straight ahead
    out = without_people(scan, [person, wall], lidar)
    a = np.angle(np.exp(1j * scan.angles.astype(np.float64)))
    ends = np.column_stack([1.0 + 2.0 * np.cos(a + math.pi / 2), 2.0 * np.sin(a + math.pi / 2)])
    near = np.hypot(ends[:, 0] - 1.0, ends[:, 1] - 2.0) <= 0.25 + MARGIN
    assert near.sum() >= 5
    assert np.isinf(out.ranges[near]).all()
    assert (out.ranges[~near] == scan.ranges[~near]).all()
    assert out.stamp == scan.stamp and out.ranges.dtype == scan.ranges.dtype


def test_with_nobody_about_or_nobody_in_view_the_scan_is_the_same():
    scan = ring()
    assert without_people(scan, [], Pose2D()) is scan
    assert without_people(scan, [Person(1, 0.5, 0.0, 0.0, 0.0, 0.2, 1.0)], Pose2D()) is scan  # inside the ring


def test_the_source_reads_the_people_and_the_lidar_pose_when_read():
    scan, people, pose = ring(), [], [Pose2D()]
    read = static_scan(lambda: scan, lambda: people, lambda: pose[0])
    assert read() is scan
    people.append(Person(1, 2.0, 0.0, 0.0, 0.0, 0.2, 1.0))  # on the wall at +x
    assert np.isinf(read().ranges).sum() > 0
    pose[0] = Pose2D(0.0, 0.0, math.pi)  # turned round: the wall at +x is behind, still hidden there
    assert np.isinf(read().ranges).sum() > 0
    assert static_scan(lambda: None, lambda: people, lambda: pose[0])() is None
