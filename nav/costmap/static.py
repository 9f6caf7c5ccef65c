"""The static layer: a map (map_server occupancy, the SLAM map once it exists) as costs.

Occupancy follows map_server's trinary mode (seed's map: occupied_thresh 0.65, free_thresh
0.25): a cell of probability p = value / 100 is lethal when p >= 0.65, free when p <= 0.25 and
unknown in between; -1 (and any value outside 0..100) is unknown. With ``track_unknown_space``
off, unknown becomes free, as in Nav2's StaticLayer.

The costmap keeps its own fixed extent (the map frame is the robot's start pose, and the map may
be smaller, larger or finer than it), so the map is sampled at every costmap cell's centre;
costmap cells outside the map are unknown. Clearing a costmap keeps the map (Nav2's StaticLayer
reset re-applies it). With equal resolution and aligned origins this is an
exact copy.
"""
from __future__ import annotations

import numpy as np

from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.grid_geometry import GridGeometry


class StaticLayer:
    def __init__(self, free_thresh: float, occupied_thresh: float, track_unknown_space: bool):
        self.free_thresh, self.occupied_thresh = free_thresh, occupied_thresh
        self.unknown = UNKNOWN if track_unknown_space else FREE
        self.costs: np.ndarray | None = None
        """uint8 costs on the costmap's cells, None until a map arrives."""

    def trinary(self, occupancy: np.ndarray) -> np.ndarray:
        occ = np.asarray(occupancy)
        known = (occ >= 0) & (occ <= 100)
        p = occ.astype(np.float64) / 100.0
        return np.where(~known, self.unknown,
                        np.where(p >= self.occupied_thresh, LETHAL,
                                 np.where(p <= self.free_thresh, FREE, self.unknown))).astype(np.uint8)

    def set_map(self, occupancy: np.ndarray, resolution: float, origin_x: float, origin_y: float,
                target: CostGrid) -> None:
        """Sample ``occupancy`` (int8 [iy, ix], map_server values) onto ``target``'s cells."""
        occ = np.asarray(occupancy)
        if occ.ndim != 2 or resolution <= 0:
            raise ValueError(f"static map: expected a 2-D occupancy grid and a positive resolution, "
                             f"got shape {occ.shape} at {resolution} m")
        cells = self.trinary(occ)
        cx, cy = target.geometry.centre_of(np.arange(target.width), np.arange(target.height))
        mx, my = GridGeometry.of(occ, resolution, origin_x, origin_y).cell_of(cx, cy)  # the map cell of each costmap column / row
        out = np.full(target.data.shape, self.unknown, dtype=np.uint8)
        cols, rows = np.nonzero((mx >= 0) & (mx < cells.shape[1]))[0], np.nonzero((my >= 0) & (my < cells.shape[0]))[0]
        out[np.ix_(rows, cols)] = cells[np.ix_(my[rows], mx[cols])]
        self.costs = out
