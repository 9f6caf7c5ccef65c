"""Segmentation of a scan: neighbouring returns closer than a jump make one segment.

The returns come in scan order (the lidar's rotation), so two returns next to each other in the
array are neighbours in angle; a gap between them wider than the jump threshold (range
dependent: the C1's angular step spreads returns with range) separates two objects. This is
leg_tracker's and DR-SPAAM's first step, vectorised: no per-point Python.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np


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

    def subset(self, keep: np.ndarray) -> "Segments":
        """The segments where ``keep`` holds, their returns renumbered contiguously (the
        caller keeps the same returns)."""
        count = self.count[keep]
        return Segments((np.cumsum(count) - count).astype(int), count,
                        self.centre[keep], self.lo[keep], self.hi[keep])

    @cached_property
    def width(self) -> np.ndarray:
        """Bounding-box diagonal of each segment, m (asked by each pass: worked out once)."""
        return np.hypot(*(self.hi - self.lo).T)


def unwrap(points: np.ndarray) -> np.ndarray:
    """Indices that put a whole revolution's returns (scan order) in the same circular order
    starting after its widest gap. The array's first and last returns are neighbours in angle
    too: the C1's (and the sim's) revolution starts straight ahead, so whatever stands dead
    ahead of the robot was cut in two at the array's ends, a pair of legs into two things, a
    box seen corner-on into its two faces. The widest gap is a break between things anyway."""
    n = len(points)
    if n < 2:
        return np.arange(n)
    before = np.hypot(*np.diff(points, axis=0, prepend=points[-1:]).T)
    return (np.arange(n) + int(np.argmax(before))) % n


def split(points: np.ndarray, ranges: np.ndarray, jump: float, jump_per_metre: float,
          index: np.ndarray | None = None) -> Segments:
    """Segments of ``points`` ((N, 2), scan order) whose ``ranges`` from the lidar are given.

    ``index``: each point's position in the whole scan, when some returns were taken out (the
    map's, a known pot's): a return taken out between two kept ones also ends a segment. A
    standing person's legs are 0.085 m apart surface to surface (centres half the 0.45 m body
    apart, radius 0.07), under the jump: what parts them is the far wall seen between them,
    which the map explains; without this they would be one segment, like a box's two faces."""
    n = len(points)
    if n == 0:
        empty = np.zeros((0, 2))
        return Segments(np.zeros(0, int), np.zeros(0, int), empty, empty, empty)
    gaps = np.hypot(*np.diff(points, axis=0).T)
    breaks = gaps > jump + jump_per_metre * np.minimum(ranges[1:], ranges[:-1])
    if index is not None:
        breaks |= np.diff(index) > 1
    start = np.flatnonzero(np.concatenate(([True], breaks)))
    count = np.diff(start, append=n)
    centre = np.add.reduceat(points, start, axis=0) / count[:, None]
    lo = np.minimum.reduceat(points, start, axis=0)
    hi = np.maximum.reduceat(points, start, axis=0)
    return Segments(start, count, centre, lo, hi)
