"""Where the aisles are, as a robot knows them: an outline each, in its own map frame.

The aisle map is the fleet's (``fleet.aisles``: found once, on the fleet's map, numbered once,
so every robot's lock on aisle 3 is the same aisle); a robot is given it as outlines, a polygon
of a few vertices each, in its own map frame like its pots, and needs only two questions of it:
which aisle a point is in, and which aisles a path crosses, in order.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NO_AISLE = -1


def _inside(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Even-odd rule, every point against every edge at once."""
    x, y = points[:, :1], points[:, 1:2]
    x0, y0 = polygon[:, 0], polygon[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    crosses = (y0 > y) != (y1 > y)
    at_x = x0 + (y - y0) * (x1 - x0) / np.where(y1 == y0, 1.0, y1 - y0)
    return (crosses & (x < at_x)).sum(axis=1) % 2 == 1


@dataclass(frozen=True)
class AisleOutlines:
    polygons: dict[int, np.ndarray]
    """Aisle id -> (K, 2) outline, map frame."""

    def at(self, points) -> np.ndarray:
        """The aisle each (N, 2) point is in, ``NO_AISLE`` on open ground."""
        points = np.asarray(points, float).reshape(-1, 2)
        out = np.full(len(points), NO_AISLE, np.int32)
        for k, polygon in sorted(self.polygons.items()):
            out[(out == NO_AISLE) & _inside(polygon, points)] = k
        return out

    def along(self, path) -> list[int]:
        """The aisles a (K, 2) path passes through, in the order it enters them (each once)."""
        return list(dict.fromkeys(int(a) for a in self.at(path) if a != NO_AISLE))
