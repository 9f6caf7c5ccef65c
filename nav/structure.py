"""The map's structure: its walls, dividers and benches, told from pots, people and crates by
their length.

An occupied component of the map whose bounding box's diagonal is longer than any pot, person or
cart (after closing gaps of a few centimetres, so a wall drawn with holes stays one piece) is
structure, or, for the person tracker, the straight runs of it (``straight_runs``: not a worker
crouching against a wall). The person tracker takes it as explained (a wall met later in the patrol is not a
person), and the map's drift is read only off neighbours on the same side of it (the two bays'
scans of one divider disagree).
"""
from __future__ import annotations

import cv2
import numpy as np

from nav.occupancy import OccupancyMap


def long_components(occupancy: OccupancyMap, min_extent: float, gap: float = 0.1,
                    run: float | None = None) -> np.ndarray:
    """Boolean [iy, ix]: the occupied cells of ``occupancy`` in components whose bounding box's
    diagonal exceeds ``min_extent`` metres once gaps up to ``gap`` are closed; with ``run``, only
    those of them on a straight run at least ``run`` metres long (``straight_runs``)."""
    res = occupancy.resolution
    occ = occupancy.occupied().astype(np.uint8)
    k = max(1, int(round(gap / res)))
    closed = cv2.morphologyEx(occ, cv2.MORPH_CLOSE, np.ones((k + 1, k + 1), np.uint8))
    n, labels, stats, _ = cv2.connectedComponentsWithStats(closed, connectivity=8)
    diagonal = np.hypot(stats[:, cv2.CC_STAT_WIDTH], stats[:, cv2.CC_STAT_HEIGHT]) * res
    long = diagonal > min_extent
    long[0] = False  # the background
    out = long[labels] & occ.astype(bool)
    return out if run is None else out & straight_runs(closed.astype(bool) & long[labels], res, run, gap)


def straight_runs(mask: np.ndarray, resolution: float, length: float, gap: float) -> np.ndarray:
    """Boolean [iy, ix]: the cells of ``mask`` within a cell of a straight run of it at least
    ``length`` metres long, gaps up to ``gap`` bridged (OpenCV's probabilistic Hough transform,
    whose sampling is seeded the same on every call: the same map, the same runs).

    Why: a long component is a wall, a divider or a bench, and whatever touches it. A worker
    crouching 5 cm from a divider was one component with it, so structure, so never tracked, and
    the robot drove by them at 0.11 m (safety.people seed 1, 1,257 s). Walls and benches are
    straight; a person's outline, a cart's included (1.2 m at most, ``PeopleConfig.max_extent``),
    has no run as long as ``length``."""
    if not mask.any():
        return np.zeros(mask.shape, bool)
    cells = max(2, int(round(length / resolution)))
    lines = cv2.HoughLinesP(mask.astype(np.uint8) * 255, 1.0, np.pi / 180, threshold=cells // 2,
                            minLineLength=cells, maxLineGap=max(1, int(round(gap / resolution))))
    drawn = np.zeros(mask.shape, np.uint8)
    for x1, y1, x2, y2 in (np.asarray(lines).reshape(-1, 4) if lines is not None else ()):
        cv2.line(drawn, (int(x1), int(y1)), (int(x2), int(y2)), 1, thickness=3)
    return drawn.astype(bool) & mask
