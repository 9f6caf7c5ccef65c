"""Where the aisles are, as a robot knows them: an outline each, in its own map frame.

The aisle map is the fleet's (``fleet.aisles``: found once, on the fleet's map, numbered once,
so every robot's lock on aisle 3 is the same aisle); a robot is given it as outlines, a polygon
of a few vertices each, in its own map frame like its pots, and needs only two questions of it:
which aisle a point is in, and which aisles a path crosses, in order; and, for a robot's body
rather than its centre, which aisles a point is within a margin of (``near``), and the cells of
a grid some aisles cover (``cells``: a planner kept out of them).
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


def _distance(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Each point's distance to the outline's edges (0 inside is not implied: see ``near``)."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    ab = b - a
    t = np.clip(((points[:, None, :] - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12), 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.hypot(*(points[:, None, :] - closest).transpose(2, 0, 1)).min(axis=1)


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

    def near(self, points, margin: float) -> list[int]:
        """The aisles any of the (N, 2) points is in or within ``margin`` of, by id."""
        points = np.asarray(points, float).reshape(-1, 2)
        if not len(points):
            return []
        return [k for k, polygon in sorted(self.polygons.items())
                if _inside(polygon, points).any() or (_distance(polygon, points) <= margin).any()]

    def cells(self, shape: tuple[int, int], resolution: float, origin: tuple[float, float], ids) -> np.ndarray:
        """A (height, width) mask of the grid cells whose centres lie in the aisles ``ids``."""
        h, w = shape
        xs = origin[0] + (np.arange(w) + 0.5) * resolution
        ys = origin[1] + (np.arange(h) + 0.5) * resolution
        mask = np.zeros(shape, bool)
        for k in ids:
            polygon = self.polygons[k]
            (x0, y0), (x1, y1) = polygon.min(axis=0), polygon.max(axis=0)
            cx = np.flatnonzero((xs >= x0) & (xs <= x1))
            cy = np.flatnonzero((ys >= y0) & (ys <= y1))
            if not (cx.size and cy.size):
                continue
            gx, gy = np.meshgrid(xs[cx], ys[cy])
            inside = _inside(polygon, np.c_[gx.ravel(), gy.ravel()]).reshape(gx.shape)
            mask[cy[0]:cy[-1] + 1, cx[0]:cx[-1] + 1] |= inside
        return mask
