"""A lidar revolution as points in ``base_link``: the only preprocessing SLAM does.

Returns outside [min_range, max_range] and ``inf`` (no return) are dropped (seed: < 0.25 m is the
robot's own arm). The points come back as 3D with z = 0, which is how kiss-icp takes a 2D scan.
The sim's scans are not smeared over the rotation, and at the base's 0.5 m/s a 0.1 s
revolution moves 5 cm at most, so there is no deskewing.
"""
from __future__ import annotations

import numpy as np

from hw.odometry import Pose2D


def scan_points(angles: np.ndarray, ranges: np.ndarray, mount: Pose2D, min_range: float,
                max_range: float) -> np.ndarray:
    """(N, 3) float64 points in ``base_link`` from one revolution taken at lidar pose ``mount``."""
    r = np.asarray(ranges, dtype=np.float64)
    keep = np.isfinite(r) & (r >= min_range) & (r <= max_range)
    a = np.asarray(angles, dtype=np.float64)[keep] + mount.yaw
    r = r[keep]
    out = np.zeros((len(r), 3))
    out[:, 0] = mount.x + r * np.cos(a)
    out[:, 1] = mount.y + r * np.sin(a)
    return out

