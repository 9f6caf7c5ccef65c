"""kiss-icp's local voxel map and point-to-point registration, in the plane, in numba.

The lidar odometry registers every scan (``nav.slam.lidar_odometry``), and with the scan
registered as it goes into the map (~350 returns at half a voxel, issue 30) kiss-icp's own
registration took 0.76 ms of a scan's 1.48 ms (median CPU time over the 180-pot patrol's
recorded scans): per returned point and iteration it looks up 27 voxels of a 3D hash map, 18
of them the empty layers above and below a 2D scan, for ~11 iterations a scan (point-to-point
ICP creeps along walls). This is the same algorithm on the same data, in two dimensions:

- the map: a voxel keeps at most ``max_points`` points, a new point is refused within
  ``voxel / sqrt(max_points)`` of one it holds, and after each scan a voxel whose first point is
  ``max_distance`` or more from the robot is dropped. Voxels live in an open-addressed hash
  table on their 2D keys (linear probing; a dropped voxel leaves a tombstone, and the table is
  rebuilt, larger when it must be, once live voxels and tombstones fill half of it);
- the registration: each point pairs with its nearest map point among the 3 x 3 voxels around
  it, if nearer than ``max_correspondence``; the Geman-McClure weight ``k^2 / (k + r^2)^2``; a
  Gauss-Newton step on (x, y, yaw) applied on the left (kiss-icp's 6-DOF system decouples for
  points at z = 0: its x, y, yaw block is this one); stop when the step's norm is below
  ``convergence`` or after ``max_iterations``.

On the same map and guess it gives kiss-icp's pose to 1e-14 (the 180-pot patrol's scans, and
``tests/nav/test_slam_planar_icp.py``) at 0.90 / 1.28 ms a scan, median and p95, against 1.59 /
2.60 ms (``nav.slam.lidar_odometry``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from hw.odometry import Pose2D

#: kiss-icp's registration defaults (KISSConfig.registration).
MAX_ITERATIONS = 500
CONVERGENCE = 1e-4
TOMB = -1
"""A slot whose voxel was dropped (probing goes on past it)."""


class VoxelMap:
    """The local map: ``(ix, iy)`` voxel keys, up to ``max_points`` points each."""

    def __init__(self, voxel: float, max_distance: float, max_points: int, slots: int = 8192):
        self.voxel, self.max_distance, self.max_points = voxel, max_distance, max_points
        self.keys = np.zeros((slots, 2), dtype=np.int64)
        self.count = np.zeros(slots, dtype=np.int64)
        """Points in each slot's voxel: 0 an empty slot, ``TOMB`` a dropped voxel's."""
        self.points = np.zeros((slots, max_points, 2), dtype=np.float64)
        self.used = np.zeros(2, dtype=np.int64)
        """Live voxels, tombstones."""

    def empty(self) -> bool:
        return int(self.used[0]) == 0

    def add(self, xy: np.ndarray) -> None:
        """Points (N, 2) already in the map's frame."""
        if 2 * (int(self.used.sum()) + len(xy)) > len(self.count):
            self._rebuild(int(self.used[0]) + len(xy))
        _add(self.keys, self.count, self.points, self.used, np.ascontiguousarray(xy[:, :2], dtype=np.float64),
             self.voxel, math.sqrt(self.voxel * self.voxel / self.max_points))

    def update(self, xy: np.ndarray, pose: Pose2D) -> None:
        """A scan's points (N, 2) in ``base_link`` at ``pose``: added, then far voxels dropped."""
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        self.add(xy[:, :2] @ np.array([[c, s], [-s, c]]) + (pose.x, pose.y))
        _drop_far(self.count, self.points, self.used, pose.x, pose.y, self.max_distance)

    def point_cloud(self) -> np.ndarray:
        """Every point held, (N, 2)."""
        live = np.flatnonzero(self.count > 0)
        return np.vstack([self.points[k, :self.count[k]] for k in live]) if len(live) else np.zeros((0, 2))

    def _rebuild(self, live: int) -> None:
        """The live voxels moved into a table of at least four slots for each (tombstones gone)."""
        slots = len(self.count)
        while slots < 4 * live:
            slots *= 2
        old = np.flatnonzero(self.count > 0)
        keys, count, points = self.keys[old], self.count[old], self.points[old]
        self.keys = np.zeros((slots, 2), dtype=np.int64)
        self.count = np.zeros(slots, dtype=np.int64)
        self.points = np.zeros((slots, self.max_points, 2), dtype=np.float64)
        _place(self.keys, self.count, self.points, keys, count, points)
        self.used[:] = (len(old), 0)


def align(xy: np.ndarray, local: VoxelMap, guess: Pose2D, max_correspondence: float, kernel: float,
          max_iterations: int = MAX_ITERATIONS, convergence: float = CONVERGENCE) -> Pose2D:
    """The pose that registers a scan's points (N, 2, in ``base_link``) to ``local``, from ``guess``."""
    if local.empty():
        return guess
    x, y, yaw = _align(np.ascontiguousarray(xy[:, :2], dtype=np.float64), local.keys, local.count, local.points,
                       local.voxel, guess.x, guess.y, guess.yaw, max_correspondence, kernel,
                       max_iterations, convergence)
    return Pose2D(x, y, yaw)


@njit(cache=True)
def _home(ix, iy, mask):
    return ((ix * 73856093) ^ (iy * 19349669)) & mask


@njit(cache=True)
def _find(keys, count, ix, iy):
    """The slot of voxel (ix, iy), or -1."""
    mask = count.shape[0] - 1
    k = _home(ix, iy, mask)
    while count[k] != 0:
        if count[k] > 0 and keys[k, 0] == ix and keys[k, 1] == iy:
            return k
        k = (k + 1) & mask
    return -1


@njit(cache=True)
def _add(keys, count, points, used, xy, voxel, spacing):
    mask = count.shape[0] - 1
    cap = points.shape[1]
    for i in range(xy.shape[0]):
        px, py = xy[i, 0], xy[i, 1]
        ix, iy = int(math.floor(px / voxel)), int(math.floor(py / voxel))
        k, free = _home(ix, iy, mask), -1
        while count[k] != 0 and not (count[k] > 0 and keys[k, 0] == ix and keys[k, 1] == iy):
            if count[k] == TOMB and free < 0:
                free = k
            k = (k + 1) & mask
        if count[k] == 0:  # a new voxel: in the first tombstone on its way, else here
            if free >= 0:
                k = free
                used[1] -= 1
            keys[k, 0], keys[k, 1] = ix, iy
            points[k, 0, 0], points[k, 0, 1] = px, py
            count[k] = 1
            used[0] += 1
            continue
        if count[k] == cap:
            continue
        near = False
        for j in range(count[k]):
            if math.sqrt((points[k, j, 0] - px) ** 2 + (points[k, j, 1] - py) ** 2) < spacing:
                near = True
                break
        if not near:
            points[k, count[k], 0], points[k, count[k], 1] = px, py
            count[k] += 1


@njit(cache=True)
def _place(keys, count, points, old_keys, old_count, old_points):
    mask = count.shape[0] - 1
    for i in range(old_count.shape[0]):
        k = _home(old_keys[i, 0], old_keys[i, 1], mask)
        while count[k] != 0:
            k = (k + 1) & mask
        keys[k] = old_keys[i]
        count[k] = old_count[i]
        points[k] = old_points[i]


@njit(cache=True)
def _drop_far(count, points, used, ox, oy, max_distance):
    limit = max_distance * max_distance
    for k in range(count.shape[0]):
        if count[k] > 0 and (points[k, 0, 0] - ox) ** 2 + (points[k, 0, 1] - oy) ** 2 >= limit:
            count[k] = TOMB
            used[0] -= 1
            used[1] += 1


@njit(cache=True)
def nearest(keys, count, points, voxel, px, py):
    """(squared distance, x, y) of the map point nearest (``px``, ``py``) among the 3 x 3 voxels
    round it; (inf, 0, 0) when they hold none."""
    ix, iy = int(math.floor(px / voxel)), int(math.floor(py / voxel))
    best, qx, qy = math.inf, 0.0, 0.0
    for dx in range(-1, 2):
        for dy in range(-1, 2):
            k = _find(keys, count, ix + dx, iy + dy)
            if k < 0:
                continue
            for j in range(count[k]):
                d = (points[k, j, 0] - px) ** 2 + (points[k, j, 1] - py) ** 2
                if d < best:
                    best, qx, qy = d, points[k, j, 0], points[k, j, 1]
    return best, qx, qy


@njit(cache=True)
def _align(xy, keys, count, points, voxel, gx, gy, gyaw, max_corr, kernel, max_iterations, convergence):
    n = xy.shape[0]
    c, s = math.cos(gyaw), math.sin(gyaw)
    src = np.empty((n, 2))
    for i in range(n):
        src[i, 0] = gx + c * xy[i, 0] - s * xy[i, 1]
        src[i, 1] = gy + s * xy[i, 0] + c * xy[i, 1]
    tc, ts, tx, ty = 1.0, 0.0, 0.0, 0.0  # the correction found so far, applied on the left
    k2 = kernel * kernel
    for _ in range(max_iterations):
        a00 = a01 = a02 = a11 = a12 = a22 = b0 = b1 = b2 = 0.0
        for i in range(n):
            px, py = src[i, 0], src[i, 1]
            best, qx, qy = nearest(keys, count, points, voxel, px, py)
            if not math.sqrt(best) < max_corr:
                continue
            rx, ry = px - qx, py - qy
            w = k2 / (kernel + best) ** 2
            # J = [[1, 0, -py], [0, 1, px]]
            a00 += w
            a11 += w
            a02 -= w * py
            a12 += w * px
            a22 += w * (px * px + py * py)
            b0 += w * rx
            b1 += w * ry
            b2 += w * (px * ry - py * rx)
        # solve A d = -b (A symmetric: [[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]])
        det = a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02)
        if det == 0.0:
            break
        r0, r1, r2 = -b0, -b1, -b2
        vx = (r0 * (a11 * a22 - a12 * a12) - a01 * (r1 * a22 - a12 * r2) + a02 * (r1 * a12 - a11 * r2)) / det
        vy = (a00 * (r1 * a22 - a12 * r2) - r0 * (a01 * a22 - a12 * a02) + a02 * (a01 * r2 - r1 * a02)) / det
        th = (a00 * (a11 * r2 - r1 * a12) - a01 * (a01 * r2 - r1 * a02) + r0 * (a01 * a12 - a11 * a02)) / det
        # exp of (vx, vy, th) in SE(2)
        ec, es = math.cos(th), math.sin(th)
        if abs(th) < 1e-10:
            ux, uy = vx, vy
        else:
            p, q = es / th, (1.0 - ec) / th
            ux, uy = p * vx - q * vy, q * vx + p * vy
        for i in range(n):
            px, py = src[i, 0], src[i, 1]
            src[i, 0] = ec * px - es * py + ux
            src[i, 1] = es * px + ec * py + uy
        tc, ts, tx, ty = ec * tc - es * ts, es * tc + ec * ts, ec * tx - es * ty + ux, es * tx + ec * ty + uy
        if math.sqrt(vx * vx + vy * vy + th * th) < convergence:
            break
    # the correction times the guess
    return tx + tc * gx - ts * gy, ty + ts * gx + tc * gy, math.atan2(ts * c + tc * s, tc * c - ts * s)
