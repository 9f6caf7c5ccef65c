"""Someone who stood in the first map: their legs, found where only that map explains returns.

The tracker's scene (``mission.runtime.greenhouse``) takes the map as it stood at the start of
the patrol for the greenhouse, so that a worker standing still later is not written away by
SLAM. The other side of it: a worker already standing there when that map was made, on a round
of one spot all patrol long (spec/world.md: a standing worker's one-point path), is part of the
greenhouse for good. They never walk off, so their cells are never seen free
(``greenhouse.seen_free``), and the robot drove up to them as to a crate: safety.people held-out
seed 109, 784-788 s, a grower standing at (6.6, 2.5) since the start, untracked from 1.3 m in,
passed at 0.11 m.

So the tracker's leg pass runs on what the structure and the known pots leave, the first map's
returns included (one pass a scan, as the tracks' legs need anyway; a second pass of its own put
perception.people's p95 per scan from ~1.2 to ~1.5 ms): a pair of legs (``perception.people.legs``:
two leg arcs with a gap between, which a crate's faces meeting at a corner are not) within ``ON``
of returns only the first map explains, within ``RANGE``, found on ``SEEN`` scans, each within
``SAME`` of the last, is someone standing; the first map's cells within ``REACH`` of them stop
explaining anything, and from the next scan they are a track like anyone unmapped, shown a
person by their legs as ever. Not on those returns alone: a leg half outside the first map's
cells is two slivers, no leg (seed 109's grower was never found so). A crouching worker there
from the start is one low block, a crate to the lidar: not found by this (the issue's front
camera would have to tell them apart).
"""
from __future__ import annotations

import math

import cv2
import numpy as np
from numba import njit

from hw.odometry import Pose2D
from nav.frames import transform_points
from nav.grid_geometry import GridGeometry

SEEN = 3
"""Scans on which a pair of legs is found at one spot before it is taken for someone standing:
as ``mission.runtime.people.LEGS_SEEN`` (one scan's pair can be two slivers of noise)."""
ON = 0.3
"""A pair whose midpoint lies this near a return only the first map explains stands there, m:
a leg's returns lie up to half a wide stance (0.2 m) and a leg's radius from the midpoint."""
SAME = 0.3
"""A pair within this of one found before is at the same spot, m (``LEGS_NEAR``)."""
FORGET = 2.0
"""A spot not seen again as legs for this long is forgotten, s."""
REACH = 0.35
"""The first map's cells within this of the pair's midpoint stop explaining returns, m: the legs
0.07 m in radius up to ~0.2 m either side of the midpoint (a wide stance) and a cell's margin;
a crate beside the worker is seen again the next time the map is frozen."""
RANGE = 3.0
"""Only returns this near the lidar count as the first map's alone, m: a leg at 3 m is ~6 of the
C1's returns, and someone farther off is not yet within the speed rule's 1 m."""


class StoodAtStart:
    """Counts pairs of legs by spot over the scans; a spot seen ``SEEN`` times is someone."""

    def __init__(self):
        self._spots: list[list[float]] = []
        """[x, y, scans seen, last seen] per spot, map frame."""

    def found(self, stamp: float, pairs: np.ndarray) -> list[tuple[float, float]]:
        """Count this scan's ``pairs`` ((K, 2) midpoints, map frame); the spots just seen for
        the ``SEEN``-th time (forgotten then: their cells are cleared once)."""
        self._spots = [s for s in self._spots if stamp - s[3] <= FORGET]
        for x, y in np.asarray(pairs, dtype=float).reshape(-1, 2):
            near = [s for s in self._spots if math.hypot(s[0] - x, s[1] - y) <= SAME]
            if near:
                near[0][:] = [x, y, near[0][2] + 1, stamp]
            else:
                self._spots.append([x, y, 1, stamp])
        sure = [(s[0], s[1]) for s in self._spots if s[2] >= SEEN]
        self._spots = [s for s in self._spots if s[2] < SEEN]
        return sure


@njit(cache=True)
def first_only(points: np.ndarray, lidar_xy: np.ndarray, explained: np.ndarray,
               bare: np.ndarray) -> np.ndarray:
    """(M, 2) the returns of ``points`` within ``RANGE`` of the lidar that only the first map
    explains (``explained`` by the whole scene, not ``bare``: its structure and known pots).
    Compiled: it runs on every scan, and its numpy version's temporaries cost more than the
    few returns it usually keeps."""
    out = np.empty_like(points)
    n = 0
    for i in range(points.shape[0]):
        if explained[i] and not bare[i] and math.hypot(points[i, 0] - lidar_xy[0], points[i, 1] - lidar_xy[1]) <= RANGE:
            out[n] = points[i]
            n += 1
    return out[:n]


def pairs_on(pairs: np.ndarray, first: np.ndarray, m2o: Pose2D) -> np.ndarray:
    """The ``pairs`` of legs (odom) within ``ON`` of a return only the first map explains
    (``first``, odom), in the map frame."""
    if not len(pairs):
        return np.empty((0, 2))
    d = np.hypot(*(pairs[:, None, :] - first[None, :, :]).transpose(2, 0, 1)).min(axis=1)
    return transform_points(m2o, pairs[d <= ON])


def clear_round(left: np.ndarray, geometry: GridGeometry, spots: list[tuple[float, float]]) -> None:
    """Mark on ``left`` (the first map's cells that no longer explain, on its ``geometry``) the
    cells within ``REACH`` of each spot (map frame)."""
    mask = np.zeros(left.shape, np.uint8)
    r = int(math.ceil(REACH / geometry.resolution))
    for x, y in spots:
        ix, iy = geometry.cell_of(x, y)
        cv2.circle(mask, (int(ix), int(iy)), r, 1, -1)
    left |= mask.astype(bool)
