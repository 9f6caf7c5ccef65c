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
"""
from __future__ import annotations

import math

import numpy as np

from nav.grid_geometry import GridGeometry
from nav.occupancy import UNKNOWN, OccupancyMap

L_HIT = math.log(0.7 / 0.3)
L_MISS = math.log(0.4 / 0.6)
L_MIN, L_MAX = -2.0, 3.5


class LogOddsGrid:
    def __init__(self, geometry: GridGeometry):
        self.geometry = geometry
        self.logodds = np.zeros(geometry.height * geometry.width, dtype=np.float32)
        self.seen = np.zeros(geometry.height * geometry.width, dtype=bool)

    def clear(self) -> None:
        self.logodds[:] = 0.0
        self.seen[:] = False

    def integrate(self, sensor_xy: tuple[float, float], ends: np.ndarray) -> None:
        """One scan: ``ends`` (N, 2) are the returns' map-frame points seen from ``sensor_xy``."""
        if len(ends) == 0:
            return
        g = self.geometry
        sx, sy = sensor_xy
        d = ends - (sx, sy)
        length = np.hypot(d[:, 0], d[:, 1])
        steps = np.maximum(np.ceil(length / (0.5 * g.resolution)).astype(np.int64), 1)
        beam = np.repeat(np.arange(len(ends)), steps)
        first = np.repeat(np.cumsum(steps) - steps, steps)
        frac = (np.arange(len(beam)) - first) / steps[beam]
        free = g.flat_index(sx + d[beam, 0] * frac, sy + d[beam, 1] * frac)
        hit = g.flat_index(ends[:, 0], ends[:, 1])
        crossed = np.zeros(self.logodds.shape, dtype=bool)
        crossed[free[free >= 0]] = True
        hit = np.unique(hit[hit >= 0])
        crossed[hit] = False
        miss = np.flatnonzero(crossed)
        self.logodds[miss] = np.maximum(self.logodds[miss] + L_MISS, L_MIN)
        self.logodds[hit] = np.minimum(self.logodds[hit] + L_HIT, L_MAX)
        self.seen[miss] = True
        self.seen[hit] = True

    def occupancy(self) -> OccupancyMap:
        """The grid as map_server values: percent of occupancy, -1 where never observed."""
        g = self.geometry
        p = 100.0 / (1.0 + np.exp(-self.logodds))
        occ = np.where(self.seen, np.rint(p), UNKNOWN).astype(np.int8).reshape(g.shape)
        return OccupancyMap(occ, g.resolution, g.origin_x, g.origin_y)
