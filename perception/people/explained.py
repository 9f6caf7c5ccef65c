"""Which returns the greenhouse itself accounts for: the static map and the known pots.

The trap: the SLAM map is built from the same scans the tracker reads, so a worker standing
still at a bench for a minute is written into the live map, and a tracker that asked the live
map "is this in the map?" would stop seeing them exactly when they matter most (someone the
robot must pass). Nor can a lidar alone tell a standing worker's outline from a crate's: a
rule that lets long-occupied cells explain returns absorbs both. So "in the map" means the map
as it stood when the patrol started (a saved map, the survey's, the previous patrol's, or the
SLAM map at the start), frozen in a :class:`StaticScene`, plus the pots the mission knows: what
the greenhouse held before anybody of interest walked in. Whoever assembles the runtime
rebuilds the scene at the start of a patrol, never from the live map during one. What the
frozen map does not hold (a crate put down since) is, near the path, treated as a person until
shown otherwise, which is the issue's rule and the safe side.

The scene is the map's occupied cells (map_server's threshold, ``OccupancyMap.occupied``) grown
by ``margin`` and the pots' discs (radius + margin) painted into the same grid once, so each
scan costs one lookup per return. Points are in the map's frame.
"""
from __future__ import annotations

import math
from typing import Optional

import cv2
import numpy as np
from numba import njit


class StaticScene:
    """The frozen occupancy of the greenhouse: map cells and known pots, grown by a margin."""

    def __init__(self, grid, pots_xy: np.ndarray, pot_radius: float, margin: float):
        """``grid``: a map_server-style map (``nav.occupancy.OccupancyMap``: its ``occupied()``
        cells and its ``geometry``) or None (no map: only the pots explain returns);
        ``pots_xy``: (P, 2) known pot centres, map frame; ``pot_radius``, ``margin``: m."""
        pots = np.ascontiguousarray(np.asarray(pots_xy, dtype=float).reshape(-1, 2))
        self.pots, self.reach = pots, pot_radius + margin
        self.geometry: Optional[object] = None
        if grid is None:
            return
        g = grid.geometry
        cells = int(np.ceil(margin / g.resolution))
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * cells + 1, 2 * cells + 1))
        static = cv2.dilate(grid.occupied().astype(np.uint8), k) if cells else grid.occupied().astype(np.uint8)
        _paint_pots(static, g.origin_x, g.origin_y, g.resolution, pots, self.reach)
        self.geometry, self.static = g, static.astype(bool).ravel()

    def explained(self, points_map: np.ndarray) -> np.ndarray:
        """(N,) bool: which of the (N, 2) map-frame returns the frozen map or a known pot
        accounts for (beyond the map, only the pots can). One compiled pass: it runs twice a
        scan, and its array version's dozen calls cost more than the lookups."""
        pts = np.ascontiguousarray(points_map, dtype=np.float64).reshape(-1, 2)
        g = self.geometry
        if g is None:
            return _explained(pts, np.zeros(0, np.bool_), 0.0, 0.0, 1.0, 0, 0, self.pots, self.reach)
        return _explained(pts, self.static, g.origin_x, g.origin_y, g.resolution, g.width, g.height,
                          self.pots, self.reach)


@njit(cache=True)
def _paint_pots(static, origin_x, origin_y, resolution, pots, reach):
    """Mark the cells whose centre lies within ``reach`` of a pot. Compiled: the scene is built
    again with every new map (1 Hz), and a 48-pot greenhouse's discs one by one in numpy were
    ~7 ms of each rebuild."""
    height, width = static.shape
    r = int(math.ceil(reach / resolution)) + 1
    for k in range(pots.shape[0]):
        ix = int(math.floor((pots[k, 0] - origin_x) / resolution))
        iy = int(math.floor((pots[k, 1] - origin_y) / resolution))
        for y in range(max(iy - r, 0), min(iy + r + 1, height)):
            for x in range(max(ix - r, 0), min(ix + r + 1, width)):
                cx, cy = origin_x + (x + 0.5) * resolution, origin_y + (y + 0.5) * resolution
                if math.hypot(cx - pots[k, 0], cy - pots[k, 1]) <= reach:
                    static[y, x] = 1


@njit(cache=True)
def _explained(pts, static, origin_x, origin_y, resolution, width, height, pots, reach):
    out = np.zeros(pts.shape[0], np.bool_)
    for i in range(pts.shape[0]):
        ix = int(math.floor((pts[i, 0] - origin_x) / resolution))
        iy = int(math.floor((pts[i, 1] - origin_y) / resolution))
        if 0 <= ix < width and 0 <= iy < height:
            out[i] = static[iy * width + ix]
            continue
        for k in range(pots.shape[0]):
            if math.hypot(pts[i, 0] - pots[k, 0], pts[i, 1] - pots[k, 1]) <= reach:
                out[i] = True
                break
    return out


def explained_mask(points_map: np.ndarray, grid, pots_xy: np.ndarray, pot_radius: float,
                   margin: float) -> np.ndarray:
    """One-off :meth:`StaticScene.explained` (build the scene once and reuse it per scan)."""
    return StaticScene(grid, pots_xy, pot_radius, margin).explained(points_map)
