"""REP-105 frames in the plane: ``map -> odom -> base_link`` as composable SE(2) poses.

Wheel odometry gives ``odom -> base_link``; a localisation source (``nav.localisation``) gives
``map -> odom``; their composition is the robot in the map, which is where goals, plans and the
global costmap live. The local costmap and MPPI work in ``odom`` (smooth, never jumps), so goals
and plans are carried from ``map`` into ``odom`` through the inverse of ``map -> odom``.
"""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D, wrap_angle, wrap_angles


def compose(a: Pose2D, b: Pose2D) -> Pose2D:
    """``a * b``: the pose ``b`` (expressed in frame ``a``) expressed in ``a``'s parent."""
    c, s = math.cos(a.yaw), math.sin(a.yaw)
    return Pose2D(a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.yaw + b.yaw))


def inverse(a: Pose2D) -> Pose2D:
    c, s = math.cos(a.yaw), math.sin(a.yaw)
    return Pose2D(-c * a.x - s * a.y, s * a.x - c * a.y, wrap_angle(-a.yaw))


def transform_points(t: Pose2D, xy: np.ndarray) -> np.ndarray:
    """Points (N, 2) given in frame ``t`` expressed in ``t``'s parent frame."""
    c, s = math.cos(t.yaw), math.sin(t.yaw)
    rot = np.array([[c, -s], [s, c]], dtype=np.float64)
    return np.asarray(xy, dtype=np.float64) @ rot.T + (t.x, t.y)


def transform_path(t: Pose2D, path: np.ndarray) -> np.ndarray:
    """Poses (N, 3) of (x, y, yaw) in frame ``t``, expressed in ``t``'s parent frame."""
    out = np.empty_like(np.asarray(path, dtype=np.float64))
    out[:, :2] = transform_points(t, path[:, :2])
    out[:, 2] = wrap_angles(path[:, 2] + t.yaw)
    return out


def distance(a: Pose2D, b: Pose2D) -> float:
    return math.hypot(a.x - b.x, a.y - b.y)


def yaw_error(a: Pose2D, b: Pose2D) -> float:
    """|a.yaw - b.yaw| wrapped to [0, pi]."""
    return abs(wrap_angle(a.yaw - b.yaw))


def to_matrix(p: Pose2D) -> np.ndarray:
    """The 4 x 4 homogeneous transform of a planar pose (kiss-icp's pose type)."""
    c, s = math.cos(p.yaw), math.sin(p.yaw)
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    m[0, 3], m[1, 3] = p.x, p.y
    return m


def from_matrix(m: np.ndarray) -> Pose2D:
    """The planar part of a 4 x 4 transform (roll, pitch and z dropped)."""
    return Pose2D(float(m[0, 3]), float(m[1, 3]), math.atan2(m[1, 0], m[0, 0]))
