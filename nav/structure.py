"""The map's structure: its walls, dividers and benches, told from pots, people and crates by
their length.

An occupied component of the map whose bounding box's diagonal is longer than any pot, person or
cart (after closing gaps of a few centimetres, so a wall drawn with holes stays one piece) is
structure. The person tracker takes it as explained (a wall met later in the patrol is not a
person; what of it is no straight run, ``odd_blobs``, may be someone against it), and the map's
drift is read only off neighbours on the same side of it (the two bays' scans of one divider
disagree).
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


def straight_runs(mask: np.ndarray, resolution: float, length: float, gap: float) -> np.ndarray:
    """Boolean [iy, ix]: the cells of ``mask`` within a cell of a straight run of it at least
    ``length`` metres long, gaps up to ``gap`` bridged (OpenCV's probabilistic Hough transform,
    seeded the same on every call: the same map, the same runs). Walls, dividers and benches are
    straight; a person's outline, a cart's included, has no run that long."""
    if not mask.any():
        return np.zeros(mask.shape, bool)
    cells = max(2, int(round(length / resolution)))
    lines = cv2.HoughLinesP(mask.astype(np.uint8) * 255, 1.0, np.pi / 180, threshold=cells // 2,
                            minLineLength=cells, maxLineGap=max(1, int(round(gap / resolution))))
    drawn = np.zeros(mask.shape, np.uint8)
    for x1, y1, x2, y2 in (np.asarray(lines).reshape(-1, 4) if lines is not None else ()):
        cv2.line(drawn, (int(x1), int(y1)), (int(x2), int(y2)), 1, thickness=3)
    return drawn.astype(bool) & mask


THIN, SEGMENT = 0.15, 1.0
"""A blob no thicker than ``THIN`` and at least ``SEGMENT`` long is a piece of wall, m: a person's
outline, a cart's side included, is shorter or thicker."""

PIECE = 0.25
"""A blob is handed on in pieces no wider than this, m: a disc round a whole blob (a wall's ragged
end 1.6 m long) would reach far beyond its cells into the aisle."""


def odd_blobs(cells, pots_xy: np.ndarray, pot_reach: float, run: float,
              max_extent: float, min_area: float, gap: float = 0.1) -> list[tuple[float, float, float]]:
    """The occupied blobs of ``cells`` (a map, or a mask of one: its ``occupied()`` and
    ``geometry``) that are neither on a straight run of at least ``run`` metres (walls, dividers,
    benches) nor within ``pot_reach`` of a known pot, of at least ``min_area`` m² and at most
    ``max_extent`` m across (bounding-box diagonal) once gaps up to ``gap`` are closed, and not
    a thin stretch of wall the transform missed: in pieces (``PIECE``), each as (centre x,
    centre y, radius), map frame.

    Why: the long components of the map are structure to the person tracker, so a worker
    crouching 5 cm from a divider, one component with it, is never tracked, and the robot drove
    by them at 0.11 m (safety.people seed 1). Read once per map, not per scan: the tracker
    asking the same question per scan (the structure as straight runs only) took every crate
    and wall corner for a track: precision 0.63 and 3 ms a scan."""
    g = cells.geometry
    res = g.resolution
    occ = cells.occupied()
    k = max(1, int(round(gap / res)))
    closed = cv2.morphologyEx(occ.astype(np.uint8), cv2.MORPH_CLOSE, np.ones((k + 1, k + 1), np.uint8)).astype(bool)
    odd = occ & ~straight_runs(closed, res, run, gap)
    known = np.zeros(occ.shape, np.uint8)
    for x, y in np.asarray(pots_xy, dtype=float).reshape(-1, 2):
        ix, iy = g.cell_of(x, y)
        cv2.circle(known, (int(ix), int(iy)), int(np.ceil(pot_reach / res)), 1, -1)
    odd &= ~known.astype(bool)
    joined = cv2.morphologyEx(odd.astype(np.uint8), cv2.MORPH_CLOSE, np.ones((k + 1, k + 1), np.uint8))
    n, labels, stats, _ = cv2.connectedComponentsWithStats(joined, connectivity=8)
    out = []
    for label in range(1, n):
        diagonal = np.hypot(stats[label, cv2.CC_STAT_WIDTH], stats[label, cv2.CC_STAT_HEIGHT]) * res
        iy, ix = np.nonzero((labels == label) & odd)
        if len(ix) * res * res < min_area or diagonal > max_extent:
            continue
        cx, cy = g.centre_of(ix, iy)
        (_, _), (w, h), _ = cv2.minAreaRect(np.stack([cx, cy], axis=1).astype(np.float32))
        if min(w, h) <= THIN and max(w, h) >= SEGMENT:
            continue  # a stretch of wall the transform missed (a short one, seen in part)
        _, piece = np.unique(np.floor(np.stack([cx, cy], axis=1) / PIECE), axis=0, return_inverse=True)
        for k in range(int(piece.max()) + 1):
            px, py = cx[piece.ravel() == k], cy[piece.ravel() == k]
            x, y = float(px.mean()), float(py.mean())
            out.append((x, y, float(np.hypot(px - x, py - y).max() + res / 2)))
    return out
