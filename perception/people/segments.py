"""Segmentation of a scan: neighbouring returns closer than a jump make one segment.

The returns come in scan order (the lidar's rotation), so two returns next to each other in the
array are neighbours in angle; a gap between them wider than the jump threshold (range
dependent: the C1's angular step spreads returns with range) separates two objects. This is
leg_tracker's and DR-SPAAM's first step, one compiled pass over the returns (numba: it runs
twice a scan, and its dozen array calls cost more than the arithmetic).
"""
from __future__ import annotations

from dataclasses import dataclass

import math

import numpy as np
from numba import njit


@dataclass(frozen=True)
class Segments:
    """Contiguous runs of returns, as arrays over the segments."""

    start: np.ndarray
    """Index of each segment's first return (int, ascending)."""
    count: np.ndarray
    """Returns per segment."""
    centre: np.ndarray
    """(S, 2) mean of each segment's returns."""
    lo: np.ndarray
    """(S, 2) lower-left corner of each segment's bounding box."""
    hi: np.ndarray
    """(S, 2) upper-right corner."""


def unwrap(points: np.ndarray) -> np.ndarray:
    """Indices that put a whole revolution's returns (scan order) in the same circular order
    starting after its widest gap. The array's first and last returns are neighbours in angle
    too: the C1's (and the sim's) revolution starts straight ahead, so whatever stands dead
    ahead of the robot was cut in two at the array's ends, a pair of legs into two things, a
    box seen corner-on into its two faces. The widest gap is a break between things anyway."""
    return _unwrap(np.ascontiguousarray(points, dtype=np.float64))


@njit(cache=True)
def _unwrap(points):
    n = points.shape[0]
    widest, after = -1.0, 0
    for i in range(n):  # the gap before each return, the first's from the last
        dx, dy = points[i, 0] - points[i - 1, 0], points[i, 1] - points[i - 1, 1]
        gap = dx * dx + dy * dy
        if gap > widest:
            widest, after = gap, i
    return (np.arange(n) + after) % max(n, 1)


@njit(cache=True)
def _split(points, ranges, jump, jump_per_metre, index):
    """``split``'s segments, one pass to find the breaks and one to sum each segment."""
    n = points.shape[0]
    starts = np.empty(n, np.int64)
    starts[0] = 0
    s = 1
    for i in range(1, n):
        dx, dy = points[i, 0] - points[i - 1, 0], points[i, 1] - points[i - 1, 1]
        gap = math.sqrt(dx * dx + dy * dy)
        if gap > jump + jump_per_metre * min(ranges[i], ranges[i - 1]) or (
                index.shape[0] and index[i] - index[i - 1] > 1):
            starts[s] = i
            s += 1
    start, count = starts[:s].copy(), np.empty(s, np.int64)
    centre, lo, hi = np.zeros((s, 2)), np.empty((s, 2)), np.empty((s, 2))
    for k in range(s):
        a, b = start[k], start[k + 1] if k + 1 < s else n
        count[k] = b - a
        for c in range(2):
            lo[k, c] = hi[k, c] = points[a, c]
            total = 0.0
            for i in range(a, b):
                v = points[i, c]
                total += v
                lo[k, c] = min(lo[k, c], v)
                hi[k, c] = max(hi[k, c], v)
            centre[k, c] = total / (b - a)
    return start, count, centre, lo, hi


def split(points: np.ndarray, ranges: np.ndarray, jump: float, jump_per_metre: float,
          index: np.ndarray | None = None) -> Segments:
    """Segments of ``points`` ((N, 2), scan order) whose ``ranges`` from the lidar are given.

    ``index``: each point's position in the whole scan, when some returns were taken out (the
    map's, a known pot's): a return taken out between two kept ones also ends a segment. A
    standing person's legs are 0.085 m apart surface to surface (centres half the 0.45 m body
    apart, radius 0.07), under the jump: what parts them is the far wall seen between them,
    which the map explains; without this they would be one segment, like a box's two faces."""
    if len(points) == 0:
        empty = np.zeros((0, 2))
        return Segments(np.zeros(0, int), np.zeros(0, int), empty, empty, empty)
    index = np.zeros(0, np.int64) if index is None else np.asarray(index, dtype=np.int64)
    return Segments(*_split(np.ascontiguousarray(points, dtype=np.float64),
                            np.ascontiguousarray(ranges, dtype=np.float64), float(jump), float(jump_per_metre), index))
