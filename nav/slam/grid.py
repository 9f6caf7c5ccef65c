"""The occupancy grid SLAM builds: log-odds per cell, every beam of a scan traced through it.

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

The beams are traced in numba (``_integrate``): each step depends on nothing but the beam, but
counting a cell once per scan needs a per-cell stamp, and the vectorised numpy version (sample
every beam, ``np.unique`` the cells) cost 13 ms for a scan reaching 6 m on average, against
under 1 ms here; re-rendering thousands of kept scans after a loop closure is what it is for
(``tests/nav/test_slam_parts.py`` holds the numpy version as the reference it must equal). An
update may be confined to a window of cells, so a correction re-renders only what it moved.

A miss within ``SURFACE_BAND`` of the surface its beam hit (``surface_shadow``: band / sin of
the incidence, back along the beam) clears no cell that leans occupied (issue 30). A wall seen
along its length is met at a grazing angle: 10 m down a wall 1 m off, at 0.1 rad, so a beam runs
within a cell of the face for its last 0.5 m, and views of one wall disagree by a centimetre or
two (the C1's 1 cm noise, a heading 2 mrad off). Every scan's far beams then cleared the face
cells the near, square-on beams hit, a miss each scan against a hit only while the robot stood
by: ``generate_world(1, 8, 1, bays=2)``'s map kept 0.88 of its walls within 10 cm (1.00 drawn at
the sim's true poses), and keeps 1.00 with this rule (replayed from the same scans).

Only cells that lean occupied (log-odds above 0) are spared, so free and unknown space is
cleared exactly as before and a grazing beam still clears what it crosses on its way: a band
that stopped every miss short of the surface (b71ff41, reverted) also left cells unseen in
front of pots and walls, which changed where the live stack drove (the far-pot patrol and the
loop-closure survey took other routes: ``tests/nav/test_slam_sim.py``'s replay poses never
read the grid, its 0.122 against 0.106 was the other route's scans). A cell that leans occupied
is still cleared by the beams that meet its surface more squarely (a box taken away, a worker
who walked on), and by every beam crossing it farther than the band from where it ends.

The band is half a cell, not a whole one. At 5 cm it also spared the stray hits a cell in front
of a wall (5-10 cm off its face: a return 4 cm short at the C1's noise and a heading a few mrad
off at range), which the grazing beams down the wall had cleared: the 180-pot greenhouse's north
wall was drawn a cell into the floor from x 30 to 35 m (its wall error 0.05, precision within a
cell 0.979; without the rule 0.02 and 1.00, replayed from one survey's scans). At 2.5 cm the
same scans draw every wall within 1.2 cm (precision within a cell 0.999) and the aisle world
above keeps all its walls (recall within 10 cm 1.00, walls within 1.6 cm).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from nav.grid_geometry import GridGeometry, paste
from nav.occupancy import UNKNOWN, OccupancyMap

L_HIT = math.log(0.7 / 0.3)
L_MISS = math.log(0.4 / 0.6)
L_MIN, L_MAX = -2.0, 3.5


GROW_STEP = 64
"""Cells a growing side is extended by at a time (3.2 m at 0.05 m)."""
SURFACE_BAND = 0.025
"""A miss nearer than this to the surface its beam hit, m, measured square to the surface,
clears no cell that leans occupied (half a cell: views of a wall disagree by 1-2 cm; a whole
cell also kept stray hits a cell in front of a wall, see the module docstring)."""
SHADOW_CAP = 1.5
"""... and that stretch reaches at most this far back along the beam, m (a wall at 12 m, the
C1's range, seen from 0.5 m off it is met at 0.04 rad: 0.6 m for a 2.5 cm band)."""


@njit(cache=True)
def surface_shadow(sx, sy, ex, ey):
    """(N,) metres before each return (``ex``, ``ey`` (N,) in scan order, seen from (sx, sy))
    within which its beam runs nearer than ``SURFACE_BAND`` to the surface it hit:
    ``SURFACE_BAND`` over the sine of the angle it meets the surface at, capped at
    ``SHADOW_CAP``. The surface is the line to a neighbour in the scan, the more grazing of
    the two: far down a wall the next beam often has no return or lands on something else, and
    the squarer side then called a 0.09 rad return 0.8 (a 6 cm shadow, not 0.55 m). An edge
    counted grazing only spares cells that lean occupied (``_integrate``)."""
    n = ex.shape[0]
    out = np.empty(n)
    for b in range(n):
        bx, by = ex[b] - sx, ey[b] - sy
        r = max(math.sqrt(bx * bx + by * by), 1e-9)
        sine = 1.0
        for o in (b - 1, b + 1):
            tx, ty = ex[o % n] - ex[b], ey[o % n] - ey[b]
            t = math.sqrt(tx * tx + ty * ty)
            sine = min(sine, abs(bx * ty - by * tx) / (r * t) if t > 1e-6 else 1.0)
        out[b] = SURFACE_BAND / max(sine, SURFACE_BAND / SHADOW_CAP)
    return out


class LogOddsGrid:
    def __init__(self, geometry: GridGeometry):
        self.geometry = geometry
        self.logodds = np.zeros(geometry.shape, dtype=np.float32)
        self._occupancy = np.full(geometry.shape, UNKNOWN, dtype=np.int8)
        """map_server values, -1 where never observed; follows ``logodds`` cell by cell."""
        self._stamp = np.zeros(geometry.shape, dtype=np.int32)
        """The last scan that touched each cell (a scan counts a cell once)."""
        self._scans = 0

    @classmethod
    def restored(cls, occupancy: OccupancyMap) -> "LogOddsGrid":
        """A grid that goes on from a map handed out earlier (a lost worker's, ``checkpoint``):
        each known cell's log-odds is the logit of its percentage (rounding costs under 0.02),
        clamped as updates are; unknown cells stay unknown until a beam crosses them."""
        grid = cls(occupancy.geometry)
        known = occupancy.occupancy >= 0
        p = np.clip(occupancy.occupancy[known].astype(np.float64) / 100.0, 1e-6, 1.0 - 1e-6)
        grid.logodds[known] = np.clip(np.log(p / (1.0 - p)), L_MIN, L_MAX)
        grid._occupancy[...] = occupancy.occupancy
        return grid

    def clear(self, window: tuple[int, int, int, int] | None = None) -> None:
        """Forget what was seen, everywhere or in the cells ``window`` = (ix0, iy0, ix1, iy1)."""
        ix0, iy0, ix1, iy1 = self._window(window)
        self.logodds[iy0:iy1, ix0:ix1] = 0.0
        self._occupancy[iy0:iy1, ix0:ix1] = UNKNOWN

    def replace(self, region: "LogOddsGrid") -> None:
        """Take ``region``'s cells (a grid on this one's lattice, inside it) in place of these:
        a re-render drawn apart is swapped in at once (``nav.slam.rerender``)."""
        dx, dy = region.geometry.offset_in(self.geometry)
        h, w = region.geometry.shape
        self.logodds[dy:dy + h, dx:dx + w] = region.logodds
        self._occupancy[dy:dy + h, dx:dx + w] = region._occupancy

    @property
    def whole(self) -> tuple[int, int, int, int]:
        """The window of every cell: an update confined to it never grows the grid."""
        return 0, 0, self.geometry.width, self.geometry.height

    def integrate(self, sensor_xy: tuple[float, float], ends: np.ndarray,
                  window: tuple[int, int, int, int] | None = None) -> None:
        """One scan: ``ends`` (N, 2) are the returns' map-frame points seen from ``sensor_xy``;
        with ``window`` (ix0, iy0, ix1, iy1), only the cells inside it are updated."""
        if len(ends) == 0:
            return
        sx, sy = sensor_xy
        if window is None:
            lo = np.minimum(ends.min(axis=0), (sx, sy))
            hi = np.maximum(ends.max(axis=0), (sx, sy))
            self._cover(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
        g = self.geometry
        ix0, iy0, ix1, iy1 = self._window(window)
        self._scans += 1
        ends = np.ascontiguousarray(ends, dtype=np.float64)
        _integrate(self.logodds.reshape(-1), self._occupancy.reshape(-1), self._stamp.reshape(-1), g.width,
                   g.origin_x, g.origin_y, g.resolution, float(sx), float(sy), ends[:, 0].copy(), ends[:, 1].copy(),
                   self._scans, ix0, iy0, ix1, iy1)

    def occupancy(self) -> OccupancyMap:
        """The grid as map_server values: percent of occupancy, -1 where never observed."""
        g = self.geometry
        return OccupancyMap(self._occupancy.copy(), g.resolution, g.origin_x, g.origin_y)

    def _window(self, window: tuple[int, int, int, int] | None) -> tuple[int, int, int, int]:
        """``window`` clipped to the grid (all of it when None): the tracer writes only inside."""
        g = self.geometry
        if window is None:
            return 0, 0, g.width, g.height
        ix0, iy0, ix1, iy1 = window
        return max(ix0, 0), max(iy0, 0), min(ix1, g.width), min(iy1, g.height)

    def _cover(self, x0: float, y0: float, x1: float, y1: float) -> None:
        grown = self.geometry.grown_to_cover(x0, y0, x1, y1, GROW_STEP)
        if grown is not self.geometry:
            self.logodds = paste(self.logodds, self.geometry, grown, 0.0)
            self._occupancy = paste(self._occupancy, self.geometry, grown, UNKNOWN)
            self._stamp = paste(self._stamp, self.geometry, grown, 0)
            self.geometry = grown


@njit(cache=True)
def _integrate(logodds, occupancy, stamp, width, ox, oy, res, sx, sy, ex, ey, scan, ix0, iy0, ix1, iy1):
    """Trace every beam from (sx, sy) to its end in half-cell steps: end cells hit, cells crossed
    before them miss (but not, within ``surface_shadow`` of the end, a cell that leans
    occupied), each cell once per scan (``stamp``: ``-scan`` marks a hit to come, ``scan`` a
    cell done), only inside the window [ix0, ix1) x [iy0, iy1)."""
    hit = -scan
    shadow = surface_shadow(sx, sy, ex, ey)
    for b in range(ex.shape[0]):
        ix, iy = int(math.floor((ex[b] - ox) / res)), int(math.floor((ey[b] - oy) / res))
        if ix0 <= ix < ix1 and iy0 <= iy < iy1:
            stamp[iy * width + ix] = hit
    for b in range(ex.shape[0]):
        dx, dy = ex[b] - sx, ey[b] - sy
        length = math.sqrt(dx * dx + dy * dy)
        steps = max(int(math.ceil(length / (0.5 * res))), 1)
        for k in range(steps):
            f = k / steps
            ix, iy = int(math.floor((sx + dx * f - ox) / res)), int(math.floor((sy + dy * f - oy) / res))
            if not (ix0 <= ix < ix1 and iy0 <= iy < iy1):
                continue
            c = iy * width + ix
            if stamp[c] == scan or stamp[c] == hit:
                continue
            if logodds[c] > 0.0 and (1.0 - f) * length < shadow[b]:
                continue  # a grazing miss on a cell that leans occupied: leave it to squarer beams
            stamp[c] = scan
            v = max(logodds[c] + L_MISS, L_MIN)
            logodds[c] = v
            occupancy[c] = np.int8(round(100.0 / (1.0 + math.exp(-v))))
    for b in range(ex.shape[0]):
        ix, iy = int(math.floor((ex[b] - ox) / res)), int(math.floor((ey[b] - oy) / res))
        if ix0 <= ix < ix1 and iy0 <= iy < iy1 and stamp[iy * width + ix] == hit:
            c = iy * width + ix
            stamp[c] = scan
            v = min(logodds[c] + L_HIT, L_MAX)
            logodds[c] = v
            occupancy[c] = np.int8(round(100.0 / (1.0 + math.exp(-v))))
