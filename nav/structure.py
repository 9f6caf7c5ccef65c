"""The map's structure: its walls, dividers and benches, told from pots, people and crates by
their length.

An occupied component of the map whose bounding box's diagonal is longer than any pot, person or
cart (after closing gaps of a few centimetres, so a wall drawn with holes stays one piece) is
structure. The person tracker takes it as explained (a wall met later in the patrol is not a
person), and the map's drift is read only off neighbours on the same side of it (the two bays'
scans of one divider disagree).
"""
from __future__ import annotations

import cv2
import numpy as np

from nav.occupancy import OccupancyMap


def long_components(occupancy: OccupancyMap, min_extent: float, gap: float = 0.1) -> np.ndarray:
    """Boolean [iy, ix]: the occupied cells of ``occupancy`` in components whose bounding box's
    diagonal exceeds ``min_extent`` metres once gaps up to ``gap`` are closed."""
    res = occupancy.resolution
    occ = occupancy.occupied().astype(np.uint8)
    k = max(1, int(round(gap / res)))
    closed = cv2.morphologyEx(occ, cv2.MORPH_CLOSE, np.ones((k + 1, k + 1), np.uint8))
    n, labels, stats, _ = cv2.connectedComponentsWithStats(closed, connectivity=8)
    diagonal = np.hypot(stats[:, cv2.CC_STAT_WIDTH], stats[:, cv2.CC_STAT_HEIGHT]) * res
    long = diagonal > min_extent
    long[0] = False  # the background
    return long[labels] & occ.astype(bool)
