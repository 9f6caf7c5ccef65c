"""An occupancy grid as map_server knows it: the one map type SLAM, map files, AMCL and the
global costmap's static layer share.

Values follow ROS's OccupancyGrid: -1 unknown, 0 free ... 100 occupied, stored int8 with row
``iy`` growing north (+y) and column ``ix`` growing east (+x); cell (0, 0) has its lower-left
corner at ``origin``. Map files flip rows on disk (PGM's first row is the top); that is
``nav.map_io``'s business, not this type's.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nav.grid_geometry import GridGeometry

UNKNOWN = -1
FREE = 0
OCCUPIED = 100
OCCUPIED_MIN = 65
"""map_server's occupied_thresh (0.65) in the map's 0..100: a cell at or above it is occupied."""
FREE_MAX = 25
"""map_server's free_thresh (0.25) in the map's 0..100: a known cell at or below it is free."""


@dataclass(frozen=True)
class OccupancyMap:
    occupancy: np.ndarray
    """int8 [iy, ix]: -1 unknown, 0..100 probability of occupancy in percent."""
    resolution: float
    """Metres per cell (seed: 0.05)."""
    origin_x: float
    """Map-frame x of cell (0, 0)'s lower-left corner, m."""
    origin_y: float
    """Map-frame y of cell (0, 0)'s lower-left corner, m."""
    origin_yaw: float = 0.0
    """map_server's origin yaw; kept for round trips (Nav2 ignores it, so do we)."""

    @property
    def height(self) -> int:
        return int(self.occupancy.shape[0])

    @property
    def width(self) -> int:
        return int(self.occupancy.shape[1])

    @property
    def geometry(self) -> GridGeometry:
        """Where the grid lies: world <-> cell <-> pixel (``nav.grid_geometry``)."""
        return GridGeometry.of(self.occupancy, self.resolution, self.origin_x, self.origin_y)

    def occupied(self, thresh: int = OCCUPIED_MIN) -> np.ndarray:
        """Boolean [iy, ix] of cells at or above ``thresh`` percent (map_server's 0.65)."""
        return self.occupancy >= thresh

    def cropped(self, margin: int = 10) -> "OccupancyMap":
        """The smallest sub-grid holding every known cell, plus ``margin`` unknown cells round
        it (as slam_toolbox sizes its maps to what was explored); the map frame is unchanged."""
        known = np.argwhere(self.occupancy >= 0)
        if len(known) == 0:
            return self
        (y0, x0), (y1, x1) = known.min(axis=0), known.max(axis=0) + 1
        y0, x0 = max(0, y0 - margin), max(0, x0 - margin)
        y1, x1 = min(self.height, y1 + margin), min(self.width, x1 + margin)
        g = self.geometry.cropped(x0, y0, x1, y1)
        return OccupancyMap(self.occupancy[y0:y1, x0:x1].copy(), self.resolution,
                            round(g.origin_x, 9), round(g.origin_y, 9), self.origin_yaw)
