"""The planner's path lengths between many points at once: what ``order: shortest`` orders by.

One NavFn wavefront (``nav.planner.propagate``) from each point, run to the whole reachable map,
gives the potential at every other point; a free cell costs NavFn's neutral 50 to cross, so the
potential over 50 is the path length in cells, longer where the path skirts inflated cost. The
field is computed on cells ``COARSEN`` times the costmap's (0.2 m), each taking the cheapest of
the fine cells it covers, so an aisle the robot fits through stays open and 200 wavefronts over
a 100 x 30 m greenhouse take seconds, not minutes; the lengths are then good to a coarse cell or
two, which is all an ordering needs. Unknown ground counts as free here (the planner itself
avoids it when it can): with a map still being built, the order assumes the greenhouse is open
where it has not been seen, rather than herding the tour into the part already mapped.
"""
from __future__ import annotations

import numpy as np

from nav.costmap.grid import UNKNOWN, CostGrid
from nav.grid_geometry import GridGeometry, paste
from nav.planner import NEUTRAL, OBSTACLE, POT_HIGH, crossing_costs, propagate

COARSEN = 4
"""Costmap cells per length-grid cell along each axis (0.05 m -> 0.2 m)."""
MARGIN = 1.0
"""Room round the points taken in when they reach past the costmap, m."""


def path_lengths(grid: CostGrid, points: np.ndarray) -> np.ndarray:
    """(N, N) path lengths in metres between world points (N, 2); ``inf`` where the planner
    finds no way (a point walled in)."""
    field = _Field(grid, points)
    out = np.stack([field.from_point(k) for k in range(len(field.flat))])
    np.fill_diagonal(out, 0.0)
    return np.minimum(out, out.T)  # the wavefront is nearly, not exactly, symmetric


def lengths_from(grid: CostGrid, origin, points: np.ndarray) -> np.ndarray:
    """(N,) path lengths in metres from ``origin`` (x, y) to each of ``points``: one wavefront."""
    field = _Field(grid, np.vstack([np.asarray(origin, dtype=float).reshape(1, 2), np.asarray(points).reshape(-1, 2)]))
    return field.from_point(0)[1:]


class _Field:
    """The coarse crossing costs round a set of points, and their cells."""

    def __init__(self, grid: CostGrid, points: np.ndarray):
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        geo = grid.geometry
        lo, hi = pts.min(axis=0) - MARGIN, pts.max(axis=0) + MARGIN
        big = geo.grown_to_cover(lo[0], lo[1], hi[0], hi[1], COARSEN)
        data = paste(grid.data, geo, big, UNKNOWN)
        cross = crossing_costs(data, allow_unknown=True)
        cross[data == UNKNOWN] = NEUTRAL
        h, w = big.height // COARSEN + 1, big.width // COARSEN + 1
        padded = np.full((h * COARSEN, w * COARSEN), OBSTACLE, np.uint8)
        padded[:big.height, :big.width] = cross
        coarse = padded.reshape(h, COARSEN, w, COARSEN).min(axis=(1, 3))  # the cheapest way through each
        self.framed = np.full((h + 2, w + 2), OBSTACLE, np.uint8)
        self.framed[1:-1, 1:-1] = coarse
        self.cells = GridGeometry(big.resolution * COARSEN, big.origin_x, big.origin_y, w, h)
        ix, iy = self.cells.cell_of(pts[:, 0], pts[:, 1])
        self.flat = (iy + 1) * (w + 2) + ix + 1
        flat_view = self.framed.ravel()
        flat_view[self.flat] = np.minimum(flat_view[self.flat], NEUTRAL)  # a point's own cell is where it stands

    def from_point(self, k: int) -> np.ndarray:
        """Path lengths from point ``k`` to every point, m."""
        pot = propagate(self.framed.ravel(), self.cells.width + 2, int(self.flat[k]), -1)[self.flat]
        return np.where(pot < POT_HIGH, pot / NEUTRAL * self.cells.resolution, np.inf)
