"""The planar registration is kiss-icp's, in two dimensions: the same local map and the same pose."""
from __future__ import annotations

import numpy as np
import pytest
from kiss_icp.mapping import VoxelHashMap
from kiss_icp.registration import Registration
from kiss_icp.voxelization import voxel_down_sample

from hw.odometry import Pose2D
from nav.frames import compose, from_matrix, to_matrix
from nav.slam.planar_icp import CONVERGENCE, MAX_ITERATIONS, VoxelMap, align
from nav.slam.scan_points import scan_points
from tests.nav.builders import RES, greenhouse_occupancy, scan_from_occupancy

MOUNT = Pose2D(0.115, 0.0, 0.0)


def drive(n: int = 80):
    """Poses along the south aisle, a turn on the spot, then up the west end (the room's frame)."""
    for k in range(n):
        if k < 40:
            yield Pose2D(1.0 + 0.1 * k, 0.5, 0.0)
        elif k < 60:
            yield Pose2D(4.9, 0.5, (k - 39) * np.pi / 40)
        else:
            yield Pose2D(4.9 - 0.1 * (k - 59), 0.5 + 0.02 * (k - 59), np.pi / 2)


@pytest.mark.parametrize("max_distance", [12.0, 2.5])  # 2.5 m: voxels are dropped as the robot goes
def test_the_planar_map_and_registration_equal_kiss_icps_scan_after_scan(max_distance):
    occ = greenhouse_occupancy()
    rng = np.random.default_rng(3)
    theirs, ours = VoxelHashMap(0.1, max_distance, 3), VoxelMap(0.1, max_distance, 3)
    registration = Registration(MAX_ITERATIONS, CONVERGENCE, 1)
    moved = 0
    for truth in drive():
        lidar = compose(truth, MOUNT)
        scan = scan_from_occupancy(occ, RES, (lidar.x, lidar.y, lidar.yaw))
        ranges = scan.ranges + rng.normal(0.0, 0.01, len(scan.ranges)).astype(np.float32)
        points = voxel_down_sample(scan_points(scan.angles, ranges, MOUNT, 0.25, 12.0), 0.05)
        guess = compose(truth, Pose2D(*rng.normal(0.0, [0.03, 0.03, 0.02])))  # a wheel-odometry-like guess
        if not ours.empty():
            want = from_matrix(registration.align_points_to_map(points, theirs, to_matrix(guess), 0.2, 0.05))
            got = align(points, ours, guess, 0.2, 0.05)
            assert got.x == pytest.approx(want.x, abs=1e-9) and got.y == pytest.approx(want.y, abs=1e-9)
            assert got.yaw == pytest.approx(want.yaw, abs=1e-9)
            moved += abs(want.x - guess.x) > 1e-3  # registration did correct the guess
        theirs.update(points, to_matrix(truth))
        ours.update(points, truth)
        want_points = np.asarray(theirs.point_cloud())[:, :2]
        assert sorted(map(tuple, np.round(ours.point_cloud(), 9))) == sorted(map(tuple, np.round(want_points, 9)))
    assert moved > 40
