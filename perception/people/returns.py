"""A scan's returns as the person tracker takes them: points in the odom frame, in scan order,
off the robot's own body, and the same points in the map frame.

Three steps a scan (the returns placed from the lidar's pose, those on the robot's outline
dropped, the rest carried into the map for the map's lookups) were three numpy passes with a
dozen temporaries, about a fifth of the people tick's cost; one compiled pass does all three
(``returns``). The body test is the collision monitor's outline (``hw.robot_outline``), grown
by the runtime's margin, not a circle round the centre: a circle of 0.25 m (the seed's
"consumers drop < 0.25 m") hid the legs of a worker who walked up to the robot's front,
0.17-0.24 m from its centre, and the robot, told of no one, went on aligning while they
touched it (safety.people seed 115 at stop 61, 516 s).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from hw.robot_outline import Outline, holds


def odom_points(scan_angles: np.ndarray, scan_ranges: np.ndarray, lidar_pose: tuple[float, float, float]) -> np.ndarray:
    """A scan's finite returns as (N, 2) points in scan order, given the lidar's pose in the
    frame wanted (odom, or map for :class:`~perception.people.explained.StaticScene`)."""
    return _odom_points(np.ascontiguousarray(scan_angles, dtype=np.float64),
                        np.ascontiguousarray(scan_ranges, dtype=np.float64), *map(float, lidar_pose))


def returns(scan_angles: np.ndarray, scan_ranges: np.ndarray, lidar_pose: tuple[float, float, float],
            robot_pose: tuple[float, float, float], body: Outline, margin: float,
            map_from_odom: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The scan's finite returns not within ``margin`` of ``body`` (the robot at ``robot_pose``),
    as (N, 2) odom points in scan order (``lidar_pose`` in odom) and the same (N, 2) in the map
    (``map_from_odom``: the odom frame's pose in the map, ``map -> odom``)."""
    return _returns(np.ascontiguousarray(scan_angles, dtype=np.float64),
                    np.ascontiguousarray(scan_ranges, dtype=np.float64), *map(float, lidar_pose),
                    *map(float, robot_pose), *map(float, map_from_odom), *body.kernel(margin))


@njit(cache=True)
def _odom_points(angles, ranges, x, y, yaw):
    out = np.empty((ranges.shape[0], 2))
    n = 0
    for i in range(ranges.shape[0]):
        if math.isfinite(ranges[i]):
            a = angles[i] + yaw
            out[n, 0], out[n, 1] = x + ranges[i] * math.cos(a), y + ranges[i] * math.sin(a)
            n += 1
    return out[:n]


@njit(cache=True)
def _returns(angles, ranges, lx, ly, lyaw, rx, ry, ryaw, mx, my, myaw,
             half_length, half_width, start, along, inverse_length2, reach2):
    odom, in_map = np.empty((ranges.shape[0], 2)), np.empty((ranges.shape[0], 2))
    rc, rs, mc, ms = math.cos(ryaw), math.sin(ryaw), math.cos(myaw), math.sin(myaw)
    n = 0
    for i in range(ranges.shape[0]):
        if not math.isfinite(ranges[i]):
            continue
        a = angles[i] + lyaw
        x, y = lx + ranges[i] * math.cos(a), ly + ranges[i] * math.sin(a)
        dx, dy = x - rx, y - ry
        if holds(rc * dx + rs * dy, rc * dy - rs * dx, half_length, half_width, start, along, inverse_length2, reach2):
            continue
        odom[n, 0], odom[n, 1] = x, y
        in_map[n, 0], in_map[n, 1] = mx + mc * x - ms * y, my + ms * x + mc * y
        n += 1
    return odom[:n], in_map[:n]
