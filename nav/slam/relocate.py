"""Finding the robot again after a shove its wheels did not feel (issue 28: carts that do not yield).

A cart pushed against the robot fills the lidar's view and carries it along the floor with its
wheels held still: safety.people seed 104 at 658.8-659.8 s, a cart pusher who does not yield
walked into the robot standing in the west aisle, slid it 0.64 m south in a second and turned it
0.19 rad, while 90-100 % of each scan's returns (median range 0.22-0.45 m) lay on the cart. The
wheel odometry felt nothing and the lidar saw nothing but the cart, so the pose stayed where the
shove began. When the cart had gone, the scans saw the greenhouse 0.64 m from where the pose
said, far past the registration's gate (3 sigma, 0.12 m), ICP settled on a wrong fit, the map
was drawn again shifted and turned, and the patrol failed on its way home (no path to the dock
through the ghost walls).

So a scan mostly on people against the robot is not registered (``nav.slam.mapper.HIDDEN``),
like a blind one, and the first scan registered after either is searched for over a window of
``REACH`` and ``TURN`` round the guess: each candidate pose on a grid is ranked by how many of
the scan's points land near the local map (on a raster of it, ``Raster``), the ``REFINED`` best
are registered as usual, and the one that then fits most points within ``INLIER`` (the nearest
point among the 3 x 3 voxels round it, as the registration pairs them) wins. The guess itself, registered, is one of them and
wins a tie, so a robot that was only leaned on, or blinded standing still, stays where it was.
Replayed on seed 104's 6,801 recorded scans: after the cart had gone the pose was 1.0 m off
for good before, 0.007 m with the search, which ran once and took 106 ms (a scan: 0.96 ms
median, the replay beside a running benchmark).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import cv2
import numpy as np
from numba import njit

from hw.odometry import Pose2D
from nav.slam.planar_icp import VoxelMap, align, nearest

REACH = 1.2
"""How far from the guess the robot is looked for, m: the longest shove seen in safety.people
carried it 0.94 m (seed 2, 4 s)."""
TURN = 0.3
"""How far its heading is looked for either way, rad (a cart shoving one corner turns it)."""
SPACING = 0.1
"""The search grid's step in x and y, m: within the registration's gate of every point."""
TURN_STEP = 0.05
"""Its step in heading, rad: 0.05 rad moves a point 5 m off by 0.25 m, but the refinement
pulls in what is within its gate."""
INLIER = 0.1
"""A point within this of the map is explained by it, m (one voxel)."""
REFINED = 6
"""Candidates refined by registration, the best scored first."""
CELL = 0.05
"""The ranking raster's cell, m (``Raster``): half of ``INLIER``, so a point is counted within
about 0.1-0.14 m of the map, near enough to rank by."""
RANKED_POINTS = 400
"""At most this many of the scan's points, evenly spread over it, rank the candidates."""
WIDE_REACH = 2.0
"""The wider window's reach, m, searched when the near one finds no pose the scan fits
(``nav.slam.lidar_odometry.FIT``): safety.people seed 106 at 563.4-565.0 s, a cart that does not
yield shoved the robot 1.3 m and turned it 0.39 rad in 1.6 s, past ``REACH`` and ``TURN``."""
WIDE_TURN = 0.6
"""The wider window's heading reach either way, rad."""


@njit(cache=True)
def _scores(xy, keys, count, points, voxel, gx, gy, gyaw, offsets, turns, inlier):
    """For each (offset, turn): how many points of ``xy`` land within ``inlier`` of the map (exact)."""
    out = np.zeros((offsets.shape[0], turns.shape[0]), dtype=np.int64)
    lim = inlier * inlier
    for t in range(turns.shape[0]):
        c, s = math.cos(gyaw + turns[t]), math.sin(gyaw + turns[t])
        for o in range(offsets.shape[0]):
            ox, oy = gx + offsets[o, 0], gy + offsets[o, 1]
            n = 0
            for i in range(xy.shape[0]):
                px = ox + c * xy[i, 0] - s * xy[i, 1]
                py = oy + s * xy[i, 0] + c * xy[i, 1]
                if nearest(keys, count, points, voxel, px, py)[0] < lim:
                    n += 1
            out[o, t] = n
    return out


@njit(cache=True)
def _raster_scores(xy, near, x0, y0, cell, gx, gy, gyaw, offsets, turns):
    """For each (offset, turn): how many points of ``xy`` fall on a cell of ``near`` (one array
    read a point: the ranking's cost, ``Raster``)."""
    out = np.zeros((offsets.shape[0], turns.shape[0]), dtype=np.int64)
    rows, cols = near.shape
    rx, ry = np.empty(xy.shape[0]), np.empty(xy.shape[0])
    for t in range(turns.shape[0]):
        c, s = math.cos(gyaw + turns[t]), math.sin(gyaw + turns[t])
        for i in range(xy.shape[0]):
            rx[i] = (c * xy[i, 0] - s * xy[i, 1] - x0) / cell
            ry[i] = (s * xy[i, 0] + c * xy[i, 1] - y0) / cell
        for o in range(offsets.shape[0]):
            ox, oy = (gx + offsets[o, 0]) / cell, (gy + offsets[o, 1]) / cell
            n = 0
            for i in range(xy.shape[0]):
                col, row = int(math.floor(rx[i] + ox)), int(math.floor(ry[i] + oy))
                if 0 <= row < rows and 0 <= col < cols and near[row, col]:
                    n += 1
            out[o, t] = n
    return out


class Raster(NamedTuple):
    """The local map's cells within about ``INLIER`` of one of its points, for ranking the
    candidates: the exact test (the nearest point among 3 x 3 voxels) cost 0.9 CPU s for the near
    window and 4.9 s for the wide one on a 1,650-point scan (a greenhouse room, synthetic), while
    a worker 5 CPU s on one scan is killed as spinning (``nav.slam.liveness``) and a lost robot
    searches every scan. A raster of ``CELL`` answers each point with one read; the ranking only
    picks the ``REFINED`` candidates to register, which are then judged exactly (``fitted``)."""

    near: np.ndarray
    x0: float
    y0: float

    @classmethod
    def of(cls, local: VoxelMap) -> "Raster":
        pts = local.point_cloud()
        reach = math.ceil(INLIER / CELL)
        x0, y0 = pts.min(axis=0) - (reach + 1) * CELL
        cells = np.floor((pts - (x0, y0)) / CELL).astype(np.int64)
        near = np.zeros(tuple(cells.max(axis=0)[::-1] + reach + 2), np.uint8)
        near[cells[:, 1], cells[:, 0]] = 1
        disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1, 2 * reach + 1))
        return cls(cv2.dilate(near, disc).astype(np.bool_), float(x0), float(y0))


def fitted(xy: np.ndarray, local: VoxelMap, pose: Pose2D) -> int:
    """How many of the points ``xy`` (N, 2, ``base_link``) at ``pose`` land within ``INLIER`` of ``local``."""
    return int(_scores(np.ascontiguousarray(xy[:, :2], dtype=np.float64), local.keys, local.count, local.points,
                       local.voxel, pose.x, pose.y, pose.yaw, np.zeros((1, 2)), np.zeros(1), INLIER)[0, 0])


def _window(reach: float) -> np.ndarray:
    steps = np.arange(-reach, reach + 1e-9, SPACING)
    gx, gy = np.meshgrid(steps, steps)
    keep = np.hypot(gx, gy) <= reach + 1e-9
    return np.column_stack([gx[keep], gy[keep]])


class Window(NamedTuple):
    """Where round the guess the robot is looked for: (x, y) offsets and heading turns."""

    offsets: np.ndarray
    turns: np.ndarray


NEAR = Window(_window(REACH), np.arange(-TURN, TURN + 1e-9, TURN_STEP))
WIDE = Window(_window(WIDE_REACH), np.arange(-WIDE_TURN, WIDE_TURN + 1e-9, TURN_STEP))


def relocate(xy: np.ndarray, local: VoxelMap, guess: Pose2D, gate: float, kernel: float,
             window: Window = NEAR) -> Pose2D:
    """The pose of the scan ``xy`` (N, 2, ``base_link``) in ``local`` found over ``window`` round
    ``guess`` (module docstring); registered as usual from the best scored candidates."""
    pts = np.ascontiguousarray(xy[:, :2], dtype=np.float64)
    raster = Raster.of(local)
    ranked = pts[::max(1, len(pts) // RANKED_POINTS)]
    scores = _raster_scores(ranked, raster.near, raster.x0, raster.y0, CELL, guess.x, guess.y, guess.yaw,
                            window.offsets, window.turns)
    best = np.argsort(scores, axis=None)[::-1][:REFINED]
    (dx, dy), turns = window.offsets.T, window.turns
    starts = [guess] + [Pose2D(guess.x + dx[o], guess.y + dy[o], guess.yaw + turns[t])
                        for o, t in zip(*np.unravel_index(best, scores.shape))]
    fits = [align(pts, local, s, gate, kernel) for s in starts]
    counts = [fitted(pts, local, p) for p in fits]
    return fits[int(np.argmax(counts))]  # the guess first: a tie keeps it
