"""The occupancy grid SLAM builds: log-odds per cell, rays cast for the whole scan at once.

Each return marks its end cell ``hit`` and every cell the beam crossed before it ``miss``
(Moravec-Elfes / Thrun's inverse sensor model, in log-odds so an update is an addition). A
beam is sampled every half cell from the sensor to its end, so no crossed cell is skipped; a
cell crossed by several beams of one scan counts once, as does a cell hit by several, and a
cell both hit and crossed in one scan counts as hit (a grazing beam must not erode a pot's
edge). Beams without a return clear nothing (no return is not evidence of free space: the
C1 also drops returns off black or glancing surfaces).

Values: one hit makes a cell occupied (logit 0.7 = 0.85 >= map_server's 0.65), three misses
make a fresh cell free (3 x -0.41 <= logit 0.25); clamping at [-2, 3.5] keeps the map able to
change its mind when a box is dropped into an aisle or taken away. Cells never observed stay
unknown (-1), which the planner may cross (allow_unknown) and the costmap shows as such.

The grid grows as the robot explores (no size to configure): a scan reaching past its edge grows
it by whole blocks of ``GROW_STEP`` cells on that side, on the same lattice, so cells copy
across exactly and growth happens every few metres of new ground, not every scan. Memory is the
explored bounding box: 5 bytes a cell, 6 MB for a 100 x 30 m greenhouse at 0.05 m. The map
handed out (``occupancy``) is kept up to date cell by cell as scans touch it, so handing it over
costs a copy, not a pass over the whole grid.
"""
from __future__ import annotations

import math

import numpy as np

from nav.grid_geometry import GridGeometry, paste
from nav.occupancy import UNKNOWN, OccupancyMap

L_HIT = math.log(0.7 / 0.3)
L_MISS = math.log(0.4 / 0.6)
L_MIN, L_MAX = -2.0, 3.5


GROW_STEP = 64
"""Cells a growing side is extended by at a time (3.2 m at 0.05 m)."""


class LogOddsGrid:
    def __init__(self, geometry: GridGeometry):
        self.geometry = geometry
        self.logodds = np.zeros(geometry.shape, dtype=np.float32)
        self._occupancy = np.full(geometry.shape, UNKNOWN, dtype=np.int8)
        """map_server values, -1 where never observed; follows ``logodds`` cell by cell."""

    def clear(self) -> None:
        self.logodds[:] = 0.0
        self._occupancy[:] = UNKNOWN

    def integrate(self, sensor_xy: tuple[float, float], ends: np.ndarray) -> None:
        """One scan: ``ends`` (N, 2) are the returns' map-frame points seen from ``sensor_xy``."""
        if len(ends) == 0:
            return
        sx, sy = sensor_xy
        lo, hi = np.minimum(ends.min(axis=0), (sx, sy)), np.maximum(ends.max(axis=0), (sx, sy))
        self._cover(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
        g = self.geometry
        d = ends - (sx, sy)
        length = np.hypot(d[:, 0], d[:, 1])
        steps = np.maximum(np.ceil(length / (0.5 * g.resolution)).astype(np.int64), 1)
        beam = np.repeat(np.arange(len(ends)), steps)
        first = np.repeat(np.cumsum(steps) - steps, steps)
        frac = (np.arange(len(beam)) - first) / steps[beam]
        free = np.unique(g.flat_index(sx + d[beam, 0] * frac, sy + d[beam, 1] * frac))
        hit = np.unique(g.flat_index(ends[:, 0], ends[:, 1]))
        free, hit = free[free >= 0], hit[hit >= 0]  # a point exactly on the far edge
        miss = np.setdiff1d(free, hit, assume_unique=True)  # hit and crossed in one scan: hit
        logodds = self.logodds.reshape(-1)
        logodds[miss] = np.maximum(logodds[miss] + L_MISS, L_MIN)
        logodds[hit] = np.minimum(logodds[hit] + L_HIT, L_MAX)
        touched = np.concatenate([miss, hit])
        self._occupancy.reshape(-1)[touched] = np.rint(100.0 / (1.0 + np.exp(-logodds[touched]))).astype(np.int8)

    def occupancy(self) -> OccupancyMap:
        """The grid as map_server values: percent of occupancy, -1 where never observed."""
        g = self.geometry
        return OccupancyMap(self._occupancy.copy(), g.resolution, g.origin_x, g.origin_y)

    def _cover(self, x0: float, y0: float, x1: float, y1: float) -> None:
        grown = self.geometry.grown_to_cover(x0, y0, x1, y1, GROW_STEP)
        if grown is not self.geometry:
            self.logodds = paste(self.logodds, self.geometry, grown, 0.0)
            self._occupancy = paste(self._occupancy, self.geometry, grown, UNKNOWN)
            self.geometry = grown
