"""The aisle map: where only one robot may be at a time (spec/fleet.md "Aisles").

An aisle is the space between two rows of pots, or any passage narrower than two robots side
by side (a doorway, a strip between a row and a wall): two robots meeting head-on there cannot
pass, so each is entered by one robot at a time (``fleet.aisle_locks``). Found from the map:

1. A row of pots is a dotted line in the occupancy grid (pots 1 m apart leave 0.8 m gaps a
   robot fits through), and a grid of pots looks the same along the rows as across them, so
   the rows come from the pots themselves: pots side by side across their ``facing`` (within
   ``ROW_GAP``) are one row, and the row is drawn into the grid as a wall from pot to pot.
2. The robot's centre may be where the map is known free at least ``robot_radius`` (0.22 m,
   the seed's robot_radius) from anything: the configuration space.
3. Two robots pass side by side where two centres ``2 * robot_radius`` apart fit: the opening
   of that space by a disc of radius ``robot_radius`` (the cells within ``robot_radius`` of a
   cell ``2 * robot_radius`` clear). Opening the configuration space, not the floor, keeps a
   short doorway in a thin wall narrow: a disc two robots wide bulges into it from either room.
4. The rest of the centre's space, in 8-connected pieces bigger than ``MIN_AREA``, are the
   aisles, numbered in the grid's raster order (deterministic for a map).

A robot gets its aisles as ``outlines`` (a polygon each, in the map frame; turned into its own
frame like its pots, ``mission.patrol.aisle_outlines``): a few vertices each, not a grid.
"""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from nav.grid_geometry import GridGeometry
from nav.occupancy import FREE_MAX, OccupancyMap

NO_AISLE = -1
ROBOT_RADIUS = 0.22
"""The navigation footprint's radius, m (seed: robot_radius 0.22; nav.costmap.config)."""
POT_RADIUS = 0.10
"""A pot's radius, m (spec/world.md: ~0.10 m): a row's wall is this thick each side."""
ROW_GAP = 1.5
"""Pots at most this far apart across their facing are neighbours in one row, m: the sims' and
a bench's 1.0 m pitch with room for a missing pot's half gap, less than a cross aisle (1.9 m,
``sim.generate``) so a row never jumps one."""
ROW_SLANT = 0.35
"""How far off the row's line (across the facing) the next pot may lie, rad (20 deg): a row
jittered by a few cm stays one, a pot in the next row (diagonally 45 deg) is not its neighbour."""
ROW_END = 0.4
"""A row's wall runs on this far past its end pots, m: a robot at an end pot's approach pose
stands in the aisle's mouth, where one coming round the corner meets it head-on, so the mouth
is the aisle's (without it the opening below gives the mouth to the cross aisle)."""
MIN_AREA = 0.03
"""Smaller pieces are not aisles, m^2: a room's corner where the opening's disc does not reach
leaves 0.015 m^2 on 5 cm cells; the neck of a 0.7 m doorway in a 0.1 m wall is 0.06 m^2 and an
aisle's band metres long."""


@dataclass(frozen=True)
class AisleMap:
    labels: np.ndarray
    """int32 [iy, ix]: the aisle a robot's centre in the cell is in, ``NO_AISLE`` on wide ground."""
    geometry: GridGeometry

    @property
    def count(self) -> int:
        return int(self.labels.max()) + 1 if self.labels.size else 0

    def at(self, x, y) -> np.ndarray:
        """The aisle at each world point (``NO_AISLE`` off the map or on wide ground)."""
        ix, iy = self.geometry.cell_of(np.asarray(x, float), np.asarray(y, float))
        inside = self.geometry.contains(ix, iy)
        out = np.full(np.shape(ix), NO_AISLE, np.int32)
        out[inside] = self.labels[iy[inside], ix[inside]]
        return out

    def along(self, path: np.ndarray) -> list[int]:
        """The aisles a path (K, 2) passes through, in the order it enters them (each once)."""
        seen = self.at(path[:, 0], path[:, 1]) if len(path) else np.zeros(0, np.int32)
        return list(dict.fromkeys(int(a) for a in seen if a != NO_AISLE))


def find_aisles(m: OccupancyMap, pots: np.ndarray | None = None, robot_radius: float = ROBOT_RADIUS) -> AisleMap:
    """The aisle map of ``m``; ``pots``: (N, 3) x, y, facing in the map's frame (the rows)."""
    res = m.resolution
    free = ((m.occupancy >= 0) & (m.occupancy <= FREE_MAX)).astype(np.uint8)
    if pots is not None and len(pots):
        _draw_rows(free, m.geometry, np.asarray(pots, float))
    clearance = (cv2.distanceTransform(free, cv2.DIST_L2, 5) - 0.5) * res  # to the blocked cell's edge
    core = (clearance >= 2 * robot_radius).astype(np.uint8)
    wide = np.zeros(free.shape, bool)
    if core.any():
        wide = cv2.distanceTransform(1 - core, cv2.DIST_L2, 5) * res <= robot_radius + res  # a cell's slack
    narrow = ((clearance >= robot_radius) & ~wide).astype(np.uint8)
    n, comp, stats, _ = cv2.connectedComponentsWithStats(narrow, connectivity=8)
    labels = np.full(comp.shape, NO_AISLE, np.int32)
    k = 0
    for c in range(1, n):
        if stats[c, cv2.CC_STAT_AREA] * res * res >= MIN_AREA:
            labels[comp == c] = k
            k += 1
    return AisleMap(labels, m.geometry)


def outlines(a: AisleMap) -> dict[int, np.ndarray]:
    """Each aisle's outline, (K, 2) world points round its boundary cells' centres (its largest
    piece: an aisle is 8-connected, so one), in the aisle map's frame."""
    out = {}
    for k in range(a.count):
        contours, _ = cv2.findContours((a.labels == k).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        cells = max(contours, key=cv2.contourArea).reshape(-1, 2)
        x, y = a.geometry.centre_of(cells[:, 0], cells[:, 1])
        out[k] = np.c_[x, y]
    return out


def rows(pots: np.ndarray) -> tuple[list[tuple[int, int]], list[tuple[int, float]]]:
    """A row's pieces: neighbouring pots side by side across their facing (index pairs), and
    the row's ends (a pot and the side along the row, +1 or -1, with no neighbour there)."""
    pairs, ends = [], []
    for i, (x, y, facing) in enumerate(pots):
        along = np.array([-np.sin(facing), np.cos(facing)])
        d = pots[:, :2] - (x, y)
        dist = np.hypot(d[:, 0], d[:, 1])
        across = np.abs(d @ np.array([np.cos(facing), np.sin(facing)]))
        off = np.arcsin(np.clip(across / np.maximum(dist, 1e-9), 0.0, 1.0))
        for side in (1.0, -1.0):
            ok = (d @ along * side > 0) & (dist <= ROW_GAP) & (off <= ROW_SLANT)
            if ok.any():
                j = int(np.flatnonzero(ok)[np.argmin(dist[ok])])
                pairs.append((min(i, j), max(i, j)))
            else:
                ends.append((i, side))
    return sorted(set(pairs)), ends


def _draw_rows(free: np.ndarray, geo: GridGeometry, pots: np.ndarray) -> None:
    """Each row a wall a pot thick from pot to pot and ``ROW_END`` on past its ends (in place)."""
    thick = max(1, int(round(2 * POT_RADIUS / geo.resolution)))
    pairs, ends = rows(pots)
    tips = [(i, pots[i, :2] + side * ROW_END * np.array([-np.sin(pots[i, 2]), np.cos(pots[i, 2])]))
            for i, side in ends]
    segments = [(pots[i, :2], pots[j, :2]) for i, j in pairs] + [(pots[i, :2], tip) for i, tip in tips]
    for a, b in segments:
        (ax, bx), (ay, by) = geo.cell_of(np.array([a[0], b[0]]), np.array([a[1], b[1]]))
        cv2.line(free, (int(ax), int(ay)), (int(bx), int(by)), 0, thickness=thick)
