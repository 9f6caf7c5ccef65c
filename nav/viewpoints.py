"""Where to look at the pots from, found in the map alone: the survey's plan for reading tags.

Pots are what the lidar sees as small things standing apart: 8-connected clusters of occupied
cells (map_server occupied: 65..100) no larger than ``max_size`` across, unlike walls, benches
and the greenhouse's frame. A cluster is the arc of the pot's side the lidar saw, so its centre of
mass lies up to a pot radius off the pot's, towards where the lidar saw it from; a look aimed
there frames the plate off centre, up to the frame's edge at the approach distance (a survey
missed a pot that way). So each cluster is fitted with a circle of the pot's radius: the centre
whose distance to the cluster's cells is nearest the radius, on the side the lidar did not see
into (a mirror fit on the seen side would have free cells inside the pot).

A pot's tag is on its aisle side, which the map cannot tell (in a greenhouse on a square grid,
aisles and the gaps along a row look alike to a lidar), so every pot gets a *look* from each of
the four sides the lattice of pots runs along: a pose ``standoff`` out (the patrol's approach
distance, where the front camera frames a plate head-on) looking back at it, kept when the
robot's body fits there (costmap below inscribed, on seen ground). The lattice's direction is
the pots' own: the mean bearing to each pot's nearest neighbour, folded into -45..45 deg, so a
greenhouse mapped from a dock at an angle to its rows still gets its looks down the aisles.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from nav.costmap.grid import INSCRIBED, UNKNOWN, CostGrid
from nav.grid_geometry import GridGeometry
from nav.occupancy import FREE_MAX, OccupancyMap


@dataclass(frozen=True)
class Look:
    x: float
    y: float
    yaw: float
    """The pose to look from, map frame (facing the pot)."""
    pot: int
    """Index of the pot looked at (``pot_blobs``)."""


FIT_STEP = 0.005
"""Spacing of the candidate centres the circle fit tries, m."""


def pot_blobs(occupancy: OccupancyMap, radius: float, max_size: float = 0.45, min_cells: int = 2) -> np.ndarray:
    """(N, 2) map-frame centres of the pots the lidar saw: the small occupied clusters, each
    fitted with a circle of the pots' ``radius`` (``pot_centre``)."""
    occupied = occupancy.occupied().astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(occupied, connectivity=8)
    res = occupancy.resolution
    small = [k for k in range(1, n) if stats[k, cv2.CC_STAT_AREA] >= min_cells
             and max(stats[k, cv2.CC_STAT_WIDTH], stats[k, cv2.CC_STAT_HEIGHT]) * res <= max_size]
    return np.array([pot_centre(occupancy, _cells(labels, stats[k], k), radius) for k in small]).reshape(-1, 2)


def _cells(labels: np.ndarray, stat: np.ndarray, k: int) -> np.ndarray:
    """(K, 2) rows, columns of cluster ``k``, looked for in its bounding box only."""
    x, y, w, h = (int(stat[c]) for c in (cv2.CC_STAT_LEFT, cv2.CC_STAT_TOP, cv2.CC_STAT_WIDTH, cv2.CC_STAT_HEIGHT))
    return np.argwhere(labels[y:y + h, x:x + w] == k) + (y, x)


def pot_centre(occupancy: OccupancyMap, cells: np.ndarray, radius: float) -> tuple[float, float]:
    """The map-frame centre of the pot whose side is ``cells`` ((K, 2) rows, columns): of the
    candidates within ``radius`` of the cells' centre of mass, the one whose distances to the cells
    are nearest ``radius`` (least squares), each seen-through cell inside the pot (within three
    quarters of its radius: slack for the grid's quantisation) costing more than any misfit."""
    g = occupancy.geometry
    pts = np.column_stack(g.centre_of(cells[:, 1], cells[:, 0]))
    mx, my = pts.mean(axis=0)
    n = math.ceil(radius / FIT_STEP)
    cx, cy = np.meshgrid(mx + np.arange(-n, n + 1) * FIT_STEP, my + np.arange(-n, n + 1) * FIT_STEP)
    keep = np.hypot(cx - mx, cy - my) <= n * FIT_STEP  # the centre of mass is always a candidate
    cand = np.column_stack([cx[keep], cy[keep]])
    misfit = ((np.hypot(pts[None, :, 0] - cand[:, None, 0], pts[None, :, 1] - cand[:, None, 1]) - radius) ** 2).mean(axis=1)
    free = _free_cells_near(occupancy, g, mx, my, 2 * radius)
    inside = np.hypot(free[None, :, 0] - cand[:, None, 0], free[None, :, 1] - cand[:, None, 1]) < 0.75 * radius
    k = int(np.argmin(misfit + inside.sum(axis=1) * radius ** 2))
    return float(cand[k, 0]), float(cand[k, 1])


def _free_cells_near(occupancy: OccupancyMap, g: GridGeometry, x: float, y: float, reach: float) -> np.ndarray:
    """(M, 2) map-frame centres of the free cells within a square of half-side ``reach``."""
    ix, iy = (int(v) for v in g.cell_of(x, y))
    r = math.ceil(reach / g.resolution)
    y0, x0 = max(iy - r, 0), max(ix - r, 0)
    patch = occupancy.occupancy[y0:iy + r + 1, x0:ix + r + 1]
    rows, cols = np.nonzero((patch >= 0) & (patch <= FREE_MAX))
    return np.column_stack(g.centre_of(x0 + cols, y0 + rows))


def lattice_angle(pots: np.ndarray) -> float:
    """The direction the pots are laid out along, -pi/4..pi/4: the mean bearing to each pot's
    nearest neighbour on a circle of period 90 deg (0 with fewer than two pots)."""
    if len(pots) < 2:
        return 0.0
    d = pots[:, None, :] - pots[None, :, :]
    dist = np.hypot(d[..., 0], d[..., 1])
    np.fill_diagonal(dist, np.inf)
    k = np.argmin(dist, axis=1)
    bearing = np.arctan2(d[np.arange(len(pots)), k, 1], d[np.arange(len(pots)), k, 0]) % (math.pi / 2)
    return float(np.angle(np.exp(4j * bearing).mean()) / 4)  # a period of 90 deg: 1 and 89 deg agree


def looks(pots: np.ndarray, costmap: CostGrid, standoff: float, slants: tuple[float, ...] = ()) -> list[Look]:
    """The looks at each pot from the four sides along the lattice where the robot fits. A side
    where it does not fit square on is looked at from ``slants`` (rad) off it instead, the first
    that fits on either hand: a pot pushed into an aisle leaves no room square in front of it
    (the pot across the aisle is in the way) but room beside that pot, and its plate still
    faces the aisle."""
    base = lattice_angle(pots)
    out = []
    for i, (px, py) in enumerate(pots):
        for k in range(4):
            a = base + k * math.pi / 2
            square = look_at(px, py, a, i, costmap, standoff)
            if square is not None:
                out.append(square)
                continue
            for hand in (1.0, -1.0):
                slanted = next((v for s in slants if (v := look_at(px, py, a + hand * s, i, costmap, standoff))), None)
                if slanted is not None:
                    out.append(slanted)
    return out


def look_at(px: float, py: float, a: float, pot: int, costmap: CostGrid, standoff: float) -> Look | None:
    """The look at the pot at (px, py) from bearing ``a``, ``standoff`` out, if the robot fits there."""
    x, y = px + standoff * math.cos(a), py + standoff * math.sin(a)
    cost = int(costmap.cost_at(x, y))
    if cost >= INSCRIBED or cost == UNKNOWN:
        return None
    return Look(float(x), float(y), math.atan2(math.sin(a + math.pi), math.cos(a + math.pi)), pot)


@dataclass(frozen=True)
class Lane:
    start: Look
    end: Look
    """The first and last look of the sweep (the same heading)."""
    looks: tuple[Look, ...]
    """Every look on it, in order from ``start``."""

    @property
    def length(self) -> float:
        return math.hypot(self.end.x - self.start.x, self.end.y - self.start.y)

    def reversed(self) -> "Lane":
        return Lane(self.end, self.start, self.looks[::-1])


def lanes(views: list[Look], angle: float, offset_bin: float = 0.2, max_gap: float = 1.6) -> list[Lane]:
    """The looks strung into sweeps: looks the same way (one of the lattice's four headings) on
    one line across it (within ``offset_bin``), in order along it, cut where two neighbours are
    more than ``max_gap`` apart (a missing pot is fine, a cross aisle or a wall between is not).
    A robot strafing from a lane's start to its end with that heading passes every pot on it
    with its camera square to the plates."""
    groups: dict[tuple[int, int], list[tuple[float, Look]]] = {}
    for v in views:
        k = int(round((v.yaw - angle) / (math.pi / 2))) % 4
        along = angle + (math.pi / 2 if k % 2 == 0 else 0.0)  # the sweep runs square to the heading
        a, n = math.cos(along), math.sin(along)
        s, t = v.x * a + v.y * n, -v.x * n + v.y * a  # along the lane, across it
        groups.setdefault((k, int(round(t / offset_bin))), []).append((s, v))
    out = []
    for members in groups.values():
        members.sort(key=lambda m: m[0])
        run = [members[0]]
        for m in members[1:]:
            if m[0] - run[-1][0] > max_gap:
                out.append(Lane(run[0][1], run[-1][1], tuple(v for _, v in run)))
                run = []
            run.append(m)
        out.append(Lane(run[0][1], run[-1][1], tuple(v for _, v in run)))
    return out
