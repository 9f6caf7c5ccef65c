"""Where a grid lies in the world: the one world <-> cell <-> pixel mapping every map, costmap,
picture and the console's map panel share, and the arithmetic of growing and shifting a grid.

A grid of ``width`` x ``height`` square cells of ``resolution`` metres; cell (ix, iy) covers
``[origin + i * res, origin + (i + 1) * res)`` on each axis, so (0, 0)'s lower-left corner is the
origin (map_server's convention, Nav2's costmaps too). Arrays on such a grid are indexed
``[iy, ix]`` with rows growing north. Pictures are drawn north up: pixel row 0 is the grid's top
edge, and ``scale`` whole pixels make one cell.

Growing and shifting keep the lattice: a new geometry's origin differs from the old one by whole
cells, so the old cells copy across exactly (:func:`paste`), as Nav2's costmap ``updateOrigin``
and its static layer's resize to a new map do.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class GridGeometry:
    resolution: float
    """Metres per cell."""
    origin_x: float
    """World x of cell (0, 0)'s lower-left corner, m."""
    origin_y: float
    width: int
    """Cells along x (columns)."""
    height: int
    """Cells along y (rows)."""

    @classmethod
    def of(cls, data: np.ndarray, resolution: float, origin_x: float, origin_y: float) -> "GridGeometry":
        """The geometry of a ``[iy, ix]`` array."""
        return cls(float(resolution), float(origin_x), float(origin_y), int(data.shape[1]), int(data.shape[0]))

    @classmethod
    def covering(cls, x0: float, y0: float, x1: float, y1: float, resolution: float) -> "GridGeometry":
        """The smallest grid of whole cells covering the world box, on the lattice through the
        world origin (so two grids covering different boxes share cell boundaries)."""
        ix0, iy0 = (math.floor(v / resolution + 1e-9) for v in (x0, y0))  # 1e-9: -12 / 0.05 is -240.00000000000003
        ix1, iy1 = (max(i + 1, math.ceil(v / resolution - 1e-9)) for i, v in ((ix0, x1), (iy0, y1)))
        return cls(resolution, ix0 * resolution, iy0 * resolution, ix1 - ix0, iy1 - iy0)

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width): an array's shape on this grid."""
        return self.height, self.width

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """World bounds (x0, x1, y0, y1) of the whole grid."""
        return (self.origin_x, self.origin_x + self.width * self.resolution,
                self.origin_y, self.origin_y + self.height * self.resolution)

    # --- world <-> cell ---------------------------------------------------------------------
    def cell_of(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Integer (ix, iy) of world points (may fall outside the grid)."""
        ix = np.floor((np.asarray(x, dtype=np.float64) - self.origin_x) / self.resolution).astype(np.int64)
        iy = np.floor((np.asarray(y, dtype=np.float64) - self.origin_y) / self.resolution).astype(np.int64)
        return ix, iy

    def centre_of(self, ix, iy) -> tuple[np.ndarray, np.ndarray]:
        """World coordinates of cell centres."""
        return (self.origin_x + (np.asarray(ix) + 0.5) * self.resolution,
                self.origin_y + (np.asarray(iy) + 0.5) * self.resolution)

    def contains(self, ix, iy) -> np.ndarray:
        ix, iy = np.asarray(ix), np.asarray(iy)
        return (ix >= 0) & (ix < self.width) & (iy >= 0) & (iy < self.height)

    def flat_index(self, x, y) -> np.ndarray:
        """Flat ``iy * width + ix`` of world points, -1 outside the grid."""
        ix, iy = self.cell_of(x, y)
        return np.where(self.contains(ix, iy), iy * self.width + ix, -1)

    # --- world -> picture --------------------------------------------------------------------
    def pixel_of(self, x, y, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """(column, row) of world points in a north-up picture of this grid at ``scale`` pixels
        per cell, as floats (round or floor as the drawing needs)."""
        return ((np.asarray(x, dtype=np.float64) - self.origin_x) / self.resolution * scale,
                (self.height - (np.asarray(y, dtype=np.float64) - self.origin_y) / self.resolution) * scale)

    # --- growing and shifting ----------------------------------------------------------------
    def shifted(self, dx_cells: int, dy_cells: int) -> "GridGeometry":
        """The same size moved by whole cells (a rolling window following the robot)."""
        return GridGeometry(self.resolution, self.origin_x + dx_cells * self.resolution,
                            self.origin_y + dy_cells * self.resolution, self.width, self.height)

    def cropped(self, ix0: int, iy0: int, ix1: int, iy1: int) -> "GridGeometry":
        """Cells ``[ix0, ix1) x [iy0, iy1)`` as a grid of their own."""
        return GridGeometry(self.resolution, self.origin_x + ix0 * self.resolution,
                            self.origin_y + iy0 * self.resolution, ix1 - ix0, iy1 - iy0)

    def grown_to_cover(self, x0: float, y0: float, x1: float, y1: float, step: int = 1) -> "GridGeometry":
        """This grid grown (never shrunk) by whole cells until it covers the world box; each
        side grows by a multiple of ``step`` cells, so a grid growing as a robot explores is
        re-allocated now and then, not on every scan."""
        def more(need: float) -> int:
            return 0 if need <= 0 else step * math.ceil(math.ceil(need / self.resolution - 1e-9) / step)

        gx0, x_hi = more(self.origin_x - x0), more(x1 - self.extent[1])
        gy0, y_hi = more(self.origin_y - y0), more(y1 - self.extent[3])
        if not (gx0 or x_hi or gy0 or y_hi):
            return self
        return GridGeometry(self.resolution, self.origin_x - gx0 * self.resolution, self.origin_y - gy0 * self.resolution,
                            self.width + gx0 + x_hi, self.height + gy0 + y_hi)

    def offset_in(self, other: "GridGeometry") -> tuple[int, int]:
        """Whole cells (dx, dy) from ``other``'s cell (0, 0) to this grid's: both on one lattice."""
        if not math.isclose(self.resolution, other.resolution, rel_tol=1e-9):
            raise ValueError(f"grids of {self.resolution} m and {other.resolution} m cells do not share a lattice")
        dx, dy = (self.origin_x - other.origin_x) / self.resolution, (self.origin_y - other.origin_y) / self.resolution
        if abs(dx - round(dx)) > 1e-6 or abs(dy - round(dy)) > 1e-6:
            raise ValueError("grid origins differ by a fraction of a cell: not one lattice")
        return int(round(dx)), int(round(dy))


def paste(data: np.ndarray, source: GridGeometry, target: GridGeometry, fill) -> np.ndarray:
    """``data`` (on ``source``) copied onto a new array on ``target``, cell for cell where the
    two overlap and ``fill`` elsewhere; both grids on one lattice (growing, shifting,
    cropping)."""
    dx, dy = source.offset_in(target)  # source cell (0, 0) sits at target cell (dx, dy)
    out = np.full(target.shape + data.shape[2:], fill, dtype=data.dtype)
    tx0, ty0 = max(dx, 0), max(dy, 0)
    tx1, ty1 = min(dx + source.width, target.width), min(dy + source.height, target.height)
    if tx0 < tx1 and ty0 < ty1:
        out[ty0:ty1, tx0:tx1] = data[ty0 - dy:ty1 - dy, tx0 - dx:tx1 - dx]
    return out
