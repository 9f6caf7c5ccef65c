"""A 2D cost grid in a metric frame: the one data type every costmap layer, the planner and the
MPPI critics share.

Values follow Nav2 (../shared/reference/mppi.md, DESIGN.md): 0 free, 1..252 inflated cost,
253 inscribed (the robot's centre here means contact), 254 lethal, 255 unknown. ``data`` is
indexed ``[iy, ix]`` (rows are y), cell (ix, iy) covers ``[origin + i * res, origin + (i+1) * res)``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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

    def world_to_cell(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Cell indices (ix, iy) of world points, as int arrays; may lie outside the grid."""
        ix = np.floor((np.asarray(x, dtype=np.float64) - self.origin_x) / self.resolution).astype(np.int64)
        iy = np.floor((np.asarray(y, dtype=np.float64) - self.origin_y) / self.resolution).astype(np.int64)
        return ix, iy

    def cell_to_world(self, ix, iy) -> tuple[np.ndarray, np.ndarray]:
        """World coordinates of cell centres."""
        return (self.origin_x + (np.asarray(ix) + 0.5) * self.resolution,
                self.origin_y + (np.asarray(iy) + 0.5) * self.resolution)

    def inside(self, ix, iy) -> np.ndarray:
        ix, iy = np.asarray(ix), np.asarray(iy)
        return (ix >= 0) & (ix < self.width) & (iy >= 0) & (iy < self.height)

    def cost_at(self, x, y, outside: int = UNKNOWN) -> np.ndarray:
        """Cost of the cells under world points (vectorised); ``outside`` beyond the grid."""
        ix, iy = self.world_to_cell(x, y)
        ok = self.inside(ix, iy)
        out = np.full(ix.shape, outside, dtype=np.uint8)
        out[ok] = self.data[iy[ok], ix[ok]]
        return out

    def copy(self) -> "CostGrid":
        return CostGrid(self.data.copy(), self.resolution, self.origin_x, self.origin_y)

    def shifted(self, dx_cells: int, dy_cells: int, fill: int) -> "CostGrid":
        """The same extent moved by whole cells (a rolling window following the robot): the
        overlap keeps its values, newly exposed cells get ``fill`` (Nav2's updateOrigin)."""
        h, w = self.data.shape
        out = np.full_like(self.data, fill)
        sx0, sx1 = max(dx_cells, 0), min(w + dx_cells, w)  # source columns still inside
        sy0, sy1 = max(dy_cells, 0), min(h + dy_cells, h)
        if sx0 < sx1 and sy0 < sy1:
            out[sy0 - dy_cells:sy1 - dy_cells, sx0 - dx_cells:sx1 - dx_cells] = self.data[sy0:sy1, sx0:sx1]
        return CostGrid(out, self.resolution, self.origin_x + dx_cells * self.resolution,
                        self.origin_y + dy_cells * self.resolution)
