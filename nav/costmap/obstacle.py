"""The obstacle layer: lidar returns mark lethal cells, the beams clear the cells they cross.

Per scan, as Nav2's ObstacleLayer: first every beam clears free space from the sensor out to
its return (or to ``raytrace_max_range``, whichever is nearer; beams are clipped at the grid's
edge), then every return within ``obstacle_max_range`` marks its cell lethal, so a beam of this
scan never erases what another beam of it saw. Returns nearer than ``obstacle_min_range`` are
dropped from both (seed: min_laser_range 0.25 "applied everywhere": the lidar sees the robot's own
arm at ~0.10 m). Beams with no return (``inf``) clear nothing unless ``inf_is_valid``. NaN and
negative ranges are garbage from the device and are ignored, never raised: this runs in a
control loop.

The layer keeps its own grid (free or unknown until observed) so clearing one update does not
fight the static layer's map; the layered costmap merges them.
"""
from __future__ import annotations

import logging

import numpy as np

from hw.interfaces import LidarScan
from nav.costmap.grid import FREE, LETHAL, CostGrid
from nav.costmap.raytrace import clear_rays
from nav.grid_geometry import GridGeometry

log = logging.getLogger(__name__)


class ObstacleLayer:
    def __init__(self, grid: CostGrid, min_range: float, mark_range: float, clear_range: float,
                 inf_is_valid: bool):
        self.grid = grid
        self.default = int(grid.data.flat[0])
        self.min_range, self.mark_range, self.clear_range = min_range, mark_range, clear_range
        self.inf_is_valid = inf_is_valid

    def reset(self) -> None:
        self.grid.data[:] = self.default

    def shift(self, dx_cells: int, dy_cells: int) -> None:
        self.grid = self.grid.shifted(dx_cells, dy_cells, self.default)

    def resize(self, geometry: GridGeometry) -> None:
        """The same observations on a grown grid (one lattice); new cells unobserved."""
        self.grid = self.grid.on(geometry, self.default)

    def update(self, scan: LidarScan, sensor_pose: tuple[float, float, float]) -> None:
        g = self.grid
        sx, sy, syaw = sensor_pose
        geo = g.geometry
        ix0, iy0 = (int(v) for v in geo.cell_of(sx, sy))
        if not geo.contains(ix0, iy0):
            log.debug("sensor at (%.2f, %.2f) is outside the costmap; scan skipped", sx, sy)
            return
        r = np.asarray(scan.ranges, dtype=np.float64)
        a = np.asarray(scan.angles, dtype=np.float64) + syaw
        with np.errstate(invalid="ignore"):
            hit = np.isfinite(r) & (r >= self.min_range) & np.isfinite(a)
            miss = np.isposinf(r) & np.isfinite(a) if self.inf_is_valid else np.zeros_like(hit)
        beam = hit | miss
        reach = np.where(hit, np.minimum(r, self.clear_range), self.clear_range)[beam]
        c, s = np.cos(a[beam]), np.sin(a[beam])
        x1, y1 = self._clip_to_grid(sx, sy, reach * c, reach * s)
        clear_rays(g.data, ix0, iy0, x1, y1, FREE)

        marks = hit & (r <= self.mark_range)
        mx, my = geo.cell_of(sx + r[marks] * np.cos(a[marks]), sy + r[marks] * np.sin(a[marks]))
        ok = geo.contains(mx, my)
        g.data[my[ok], mx[ok]] = LETHAL

    def _clip_to_grid(self, sx: float, sy: float, dx: np.ndarray, dy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """End cells of beams from the sensor (inside the grid), shortened to stay inside it."""
        g = self.grid
        u0, v0 = (sx - g.origin_x) / g.resolution, (sy - g.origin_y) / g.resolution
        du, dv = dx / g.resolution, dy / g.resolution
        hi_u, hi_v = g.width - 1e-6, g.height - 1e-6
        with np.errstate(divide="ignore", invalid="ignore"):
            tu = np.where(du > 0, (hi_u - u0) / du, np.where(du < 0, -u0 / du, np.inf))
            tv = np.where(dv > 0, (hi_v - v0) / dv, np.where(dv < 0, -v0 / dv, np.inf))
        t = np.clip(np.minimum(np.minimum(tu, tv), 1.0), 0.0, 1.0)
        x1 = np.clip(np.floor(u0 + t * du).astype(np.int64), 0, g.width - 1)
        y1 = np.clip(np.floor(v0 + t * dv).astype(np.int64), 0, g.height - 1)
        return x1, y1
