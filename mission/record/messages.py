"""Foxglove message builders: stamps, quaternions, transforms, poses, grids and scans.

Pure functions from the runtime's numbers to foxglove-sdk messages (``mission.record.channels``
decides what goes where and when). Frames follow REP-103/105; an optical frame has z along the
view, x to the image's right, y down.
"""
from __future__ import annotations

import math

import numpy as np
from foxglove.messages import (FrameTransform, Grid, PackedElementField, PackedElementFieldNumericType, Pose,
                               Quaternion, Timestamp, Vector2, Vector3)

from hw.interfaces import LidarScan
from hw.odometry import Pose2D


def ns(t: float) -> int:
    """Runtime seconds as integer nanoseconds (the scheduler's own unit)."""
    return round(t * 1e9)


def stamp(t: float) -> Timestamp:
    n = ns(t)
    return Timestamp(sec=n // 1_000_000_000, nsec=n % 1_000_000_000)


def quaternion(q: tuple[float, float, float, float]) -> Quaternion:
    x, y, z, w = (float(v) for v in q)
    return Quaternion(x=x, y=y, z=z, w=w)


def yaw_quaternion(yaw: float) -> Quaternion:
    return quaternion((0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)))


def matrix_quaternion(r: np.ndarray) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a proper rotation matrix (Shepperd's method: the branch on the largest
    of the trace and the diagonal keeps it well conditioned)."""
    t = float(np.trace(r))
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        return (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0]
    q[i] = s / 4
    q[j] = (r[j, i] + r[i, j]) / s
    q[k] = (r[k, i] + r[i, k]) / s
    return q[0], q[1], q[2], (r[k, j] - r[j, k]) / s


def transform(t: Timestamp, parent: str, child: str, x: float, y: float, z: float,
              rotation: Quaternion) -> FrameTransform:
    return FrameTransform(timestamp=t, parent_frame_id=parent, child_frame_id=child,
                          translation=Vector3(x=x, y=y, z=z), rotation=rotation)


def planar(t: Timestamp, parent: str, child: str, p: Pose2D, z: float = 0.0) -> FrameTransform:
    return transform(t, parent, child, p.x, p.y, z, yaw_quaternion(p.yaw))


def point_pose(x: float, y: float, z: float = 0.0, yaw: float = 0.0) -> Pose:
    return Pose(position=Vector3(x=float(x), y=float(y), z=float(z)), orientation=yaw_quaternion(yaw))


def optical_rotation(axis: np.ndarray, pan: float) -> tuple[float, float, float, float]:
    """An optical frame (z along ``axis``, x to the image's right) for the wrist camera, whose
    axis lies in the vertical plane of the arm's pan angle: right is that plane's normal."""
    z = axis / np.linalg.norm(axis)
    x = np.array([math.sin(pan), -math.cos(pan), 0.0])
    y = np.cross(z, x)
    return matrix_quaternion(np.column_stack([x, y, z]))


def uniform_scan(scan: LidarScan) -> tuple[float, float, np.ndarray]:
    """(start, end, ranges) at equally spaced angles, as LaserScan assumes. The sim's scans are
    already; a real RPLidar's measured angles are binned (nearest return per bin)."""
    a, r = scan.angles, scan.ranges
    n = len(a)
    if n < 2:
        return 0.0, 0.0, np.asarray(r, dtype=np.float64)
    step = (float(a[-1]) - float(a[0])) / (n - 1)
    if step > 0 and float(np.max(np.abs(np.diff(a) - step))) < 0.25 * step:
        return float(a[0]), float(a[-1]), np.asarray(r, dtype=np.float64)
    bins = np.full(n, np.inf)
    k = np.rint(np.mod(a, 2 * math.pi) / (2 * math.pi) * n).astype(np.int64) % n  # the nearest beam
    np.minimum.at(bins, k, r)
    return 0.0, 2 * math.pi * (n - 1) / n, bins


def grid_message(t: Timestamp, frame: str, data: np.ndarray, resolution: float, ox: float, oy: float,
                 field: str, kind: PackedElementFieldNumericType) -> Grid:
    """A one-byte-per-cell Grid; rows are +y (both our grids are [iy, ix]), the pose its corner."""
    h, w = data.shape
    return Grid(timestamp=t, frame_id=frame, pose=point_pose(ox, oy), column_count=w,
                cell_size=Vector2(x=resolution, y=resolution), row_stride=w, cell_stride=1,
                fields=[PackedElementField(name=field, offset=0, type=kind)],
                data=np.ascontiguousarray(data).tobytes())
