"""A 2D cost grid in a metric frame: the one data type every costmap layer, the planner and the
MPPI critics share.

Values follow Nav2 (../shared/reference/mppi.md, DESIGN.md): 0 free, 1..252 inflated cost,
253 inscribed (the robot's centre here means contact), 254 lethal, 255 unknown. ``data`` is
indexed ``[iy, ix]`` (rows are y), cell (ix, iy) covers ``[origin + i * res, origin + (i+1) * res)``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nav.grid_geometry import GridGeometry, paste

FREE = 0
INSCRIBED = 253
LETHAL = 254
UNKNOWN = 255


@dataclass
class CostGrid:
    data: np.ndarray  # uint8 (height, width), [iy, ix]
    resolution: float  # metres per cell
    origin_x: float  # world x of the lower-left corner of cell (0, 0)
    origin_y: float

    @classmethod
    def filled(cls, width: int, height: int, resolution: float, origin_x: float, origin_y: float,
               value: int = FREE) -> "CostGrid":
        return cls(np.full((height, width), value, dtype=np.uint8), resolution, origin_x, origin_y)

    @property
    def width(self) -> int:
        return self.data.shape[1]

    @property
    def height(self) -> int:
        return self.data.shape[0]

    @property
    def geometry(self) -> GridGeometry:
        """Where the grid lies: world <-> cell <-> pixel (``nav.grid_geometry``)."""
        return GridGeometry.of(self.data, self.resolution, self.origin_x, self.origin_y)

    def cost_at(self, x, y, outside: int = UNKNOWN) -> np.ndarray:
        """Cost of the cells under world points (vectorised); ``outside`` beyond the grid."""
        g = self.geometry
        ix, iy = g.cell_of(x, y)
        ok = g.contains(ix, iy)
        out = np.full(ix.shape, outside, dtype=np.uint8)
        out[ok] = self.data[iy[ok], ix[ok]]
        return out

    def copy(self) -> "CostGrid":
        return CostGrid(self.data.copy(), self.resolution, self.origin_x, self.origin_y)

    def shifted(self, dx_cells: int, dy_cells: int, fill: int) -> "CostGrid":
        """The same extent moved by whole cells (a rolling window following the robot): the
        overlap keeps its values, newly exposed cells get ``fill`` (Nav2's updateOrigin)."""
        g = self.geometry
        moved = g.shifted(dx_cells, dy_cells)
        return CostGrid(paste(self.data, g, moved, fill), self.resolution, moved.origin_x, moved.origin_y)

    def on(self, geometry: GridGeometry, fill: int) -> "CostGrid":
        """The same cells on another grid of the same lattice (grown, shifted or cropped)."""
        return CostGrid(paste(self.data, self.geometry, geometry, fill), geometry.resolution,
                        geometry.origin_x, geometry.origin_y)
