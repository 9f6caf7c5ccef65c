"""The inflation layer: Nav2's exponential halo around lethal cells.

For a cell at distance d from the nearest lethal cell (seed: robot_radius 0.22 = the inscribed
radius, inflation_radius 0.25, cost_scaling_factor 5.0; formula as Nav2's InflationLayer):

    d == 0                         254  lethal
    d <= inscribed radius          253  inscribed: the robot's centre here means contact
    d <= inflation radius (cells)  int(252 * exp(-5.0 * (d - 0.22)))
    beyond                         unchanged

Distances are Euclidean between cell centres and the cutoff is ``ceil(inflation_radius /
resolution)`` cells, as in Nav2, so at 0.05 m the halo is five cells: 253 out to sqrt(19) cells,
then 247 (sqrt(20)) down to 216 (5 cells). Unknown cells follow Nav2 with ``inflate_unknown``
false: only lethal cells are sources, and an unknown cell takes an inflated cost only when it is
inscribed (253), otherwise it stays 255; every other cell keeps the maximum of its own cost and
the inflated one.

Two implementations of the same function. ``inflate`` (the one the costmaps use) stamps a
precomputed disc of costs around every *boundary* lethal cell (one with a non-lethal 4-neighbour:
the nearest lethal cell to any free cell is always one, so interior cells never matter), in
numba; its work grows with the obstacle boundary, not the map. ``inflate_edt`` is the vectorised
reference: OpenCV's exact Euclidean distance transform plus a table lookup. They agree cell for
cell (tests); the benchmark measures both, since on one core the transform over a 2000 x 2000 map
alone takes longer than the 50 ms goal.
"""
from __future__ import annotations

import math

import cv2
import numpy as np
from numba import njit

from nav.costmap.grid import INSCRIBED, LETHAL, UNKNOWN


def cell_radius(inflation_radius: float, resolution: float) -> int:
    """Nav2's cellDistance: the halo in whole cells, rounded up."""
    return max(0, math.ceil(inflation_radius / resolution - 1e-9))


def cost_of_squared_distance(k: np.ndarray, resolution: float, inscribed_radius: float,
                             inflation_radius: float, cost_scaling_factor: float) -> np.ndarray:
    """Inflated cost for squared cell distances ``k`` (integers), Nav2's computeCost."""
    k = np.asarray(k, dtype=np.int64)
    d = np.sqrt(k) * resolution
    r = cell_radius(inflation_radius, resolution)
    decay = ((INSCRIBED - 1) * np.exp(-cost_scaling_factor * (d - inscribed_radius))).astype(np.int64)
    cost = np.where(k > r * r, 0, np.where(d <= inscribed_radius, INSCRIBED, decay))
    return np.where(k == 0, LETHAL, cost).astype(np.uint8)


class InflationLayer:
    """Inflates a master grid of layer costs (0 free, 254 lethal, 255 unknown) into the final costs."""

    def __init__(self, resolution: float, inscribed_radius: float, inflation_radius: float,
                 cost_scaling_factor: float):
        self.params = (resolution, inscribed_radius, inflation_radius, cost_scaling_factor)
        r = cell_radius(inflation_radius, resolution)
        dy, dx = np.mgrid[-r:r + 1, -r:r + 1]
        k = dx * dx + dy * dy
        cost = cost_of_squared_distance(k, *self.params)
        keep = (k > 0) & (cost > 0)
        self._dy = dy[keep].astype(np.int64)
        self._dx = dx[keep].astype(np.int64)
        self._cost = cost[keep]

    def apply(self, master: np.ndarray) -> np.ndarray:
        """A new array: ``master`` with the halo added."""
        return inflate(master, self._dy, self._dx, self._cost)

    def apply_edt(self, master: np.ndarray) -> np.ndarray:
        """The same result through OpenCV's distance transform (reference, benchmark)."""
        return inflate_edt(master, *self.params)


@njit(cache=True)
def inflate(master, dy, dx, cost):
    h, w = master.shape
    out = master.copy()
    for y in range(h):
        for x in range(w):
            if master[y, x] != LETHAL:
                continue
            if not ((x > 0 and master[y, x - 1] != LETHAL) or (x < w - 1 and master[y, x + 1] != LETHAL)
                    or (y > 0 and master[y - 1, x] != LETHAL) or (y < h - 1 and master[y + 1, x] != LETHAL)):
                continue  # interior: never the nearest lethal cell of a non-lethal one
            for i in range(cost.size):
                yy = y + dy[i]
                xx = x + dx[i]
                if yy < 0 or yy >= h or xx < 0 or xx >= w:
                    continue
                c = cost[i]
                old = out[yy, xx]
                if old == UNKNOWN:
                    if c >= INSCRIBED:
                        out[yy, xx] = c
                elif c > old:
                    out[yy, xx] = c
    return out


def inflate_edt(master: np.ndarray, resolution: float, inscribed_radius: float, inflation_radius: float,
                cost_scaling_factor: float) -> np.ndarray:
    r = cell_radius(inflation_radius, resolution)
    free = cv2.compare(master, LETHAL, cv2.CMP_NE)  # distanceTransform measures to zero pixels
    d = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    k = np.minimum(np.rint(d * d), r * r + 1).astype(np.int64)
    table = cost_of_squared_distance(np.arange(r * r + 2), resolution, inscribed_radius, inflation_radius,
                                     cost_scaling_factor)
    cost = table[k]
    unknown = master == UNKNOWN
    return np.where(unknown, np.where(cost >= INSCRIBED, cost, UNKNOWN), np.maximum(master, cost)).astype(np.uint8)
