"""How far the robot's map has drifted from the mission's frame, here: read off the pots.

A mission's pot poses are in the frame the map had when they were written (the survey's map, or
the world's). SLAM's map drifts from that frame slowly and smoothly, a few centimetres over tens
of metres (on a 36 m two-bay greenhouse, 5-10 cm at the far end), so a pot's tag read at arrival
places it off the mission's pose by the drift even when nobody touched it. With ``moved_xy`` at
5 cm, 143 to 164 of 180 unmoved pots there were reported ``moved``.

Drift is shared by neighbours; a moved pot is alone. So the offsets (measured minus mission) of
the pots already located near a pot say what its offset would be had it not moved: when at least
``MIN_NEIGHBOURS`` of them within ``radius``, and more than half of them, agree (lie within half
of ``moved_xy`` of the neighbours' median offset), their mean is the local drift, and the pot has
moved only when its own offset is farther than ``moved_xy`` from it. A few moved pots among the
neighbours are outvoted; where they do not agree, or there are too few (the first two pots of a
patrol, or the first past a bay's divider), the drift is taken as zero for the approach, and
the pot's moved verdict is provisional: at the patrol's end it is judged again against every
pot located by then (``PotFinder.rejudge``). Neighbours beyond a wall of the map do not count
(``walls_apart``): the two bays' scans of one divider disagree, so one bay's drift says nothing
of the other's. The robot also approaches each pot at the
mission's pose carried by the drift there, so a pot off by the drift alone is stood at right the
first time (on that greenhouse one stood at 7.6 cm off missed its bloom). The report still gives
a moved pot's position in the mission's frame (``in_mission_frame``: measured less the drift
there), which ``mission update`` writes back, so the next patrol does not find it moved again.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from behaviours.visit import PotVisit
from nav.occupancy import OccupancyMap
from nav.structure import long_components

MIN_NEIGHBOURS = 2
"""Located pots that must agree before their offset counts as the map's drift."""

WALL_EXTENT = 1.5
"""A component of the map longer than this (bounding box diagonal, m) is a wall between pots;
pots (0.2 m), their foliage and a row's neighbours in the lidar's shadow are not."""

Apart = Callable[[tuple[float, float], tuple[float, float]], bool]
"""Whether a wall of the map stands between two mission positions."""


def same_side(_a, _b) -> bool:
    """No map (a test, or before SLAM's first map): every neighbour counts."""
    return False


def walls_apart(occupancy: OccupancyMap | None, step: float = 0.05) -> Apart:
    """``Apart`` on ``occupancy``: a cell of the map's structure (``nav.structure``: walls,
    dividers, benches longer than ``WALL_EXTENT``) on the straight line between the two
    positions. Across a bay's divider the two bays' scans of the same wall disagree, so the map's
    drift on one side is no guide to the other's (on the 180-pot greenhouse the first pots past
    the divider were reported moved by the other bay's drift)."""
    if occupancy is None:
        return same_side
    walls = long_components(occupancy, WALL_EXTENT)
    g = occupancy.geometry

    def apart(a, b) -> bool:
        n = max(2, int(np.hypot(b[0] - a[0], b[1] - a[1]) / step) + 1)
        ix, iy = g.cell_of(np.linspace(a[0], b[0], n), np.linspace(a[1], b[1], n))
        inside = g.contains(ix, iy)
        return bool(walls[iy[inside], ix[inside]].any())

    return apart


class MapDrift:
    def __init__(self, radius: float, agree: float):
        self.radius, self.agree = radius, agree
        self._at: list[tuple[float, float]] = []
        self._offset: list[tuple[float, float]] = []
        self.apart: Apart = same_side
        """Which neighbours stand beyond a wall (``walls_apart`` on the map as it is)."""

    def record(self, mission_xy: tuple[float, float], offset: tuple[float, float]) -> None:
        """A located pot's offset, measured minus mission, at its mission position."""
        self._at.append(mission_xy)
        self._offset.append(offset)

    def near(self, x: float, y: float) -> tuple[float, float]:
        """The map's drift at mission position (x, y): (dx, dy), zero when it cannot be told."""
        return self.consensus(x, y) or (0.0, 0.0)

    def consensus(self, x: float, y: float, skip: tuple[float, float] | None = None) -> tuple[float, float] | None:
        """The drift at (x, y) when at least ``MIN_NEIGHBOURS`` located pots within ``radius`` on
        this side of any wall (not the one at ``skip``), and most of them, agree; None when they
        cannot tell."""
        if len(self._at) < MIN_NEIGHBOURS:
            return None
        at, off = np.asarray(self._at), np.asarray(self._offset)
        mine = np.hypot(at[:, 0] - x, at[:, 1] - y) <= self.radius
        if skip is not None:
            mine &= (at[:, 0] != skip[0]) | (at[:, 1] != skip[1])
        idx = [i for i in np.flatnonzero(mine) if not self.apart((x, y), tuple(at[i]))]
        off = off[idx]
        if len(off) < MIN_NEIGHBOURS:
            return None
        agree = off[np.hypot(*(off - np.median(off, axis=0)).T) <= self.agree]
        if len(agree) < MIN_NEIGHBOURS or 2 * len(agree) <= len(off):
            return None
        mean = agree.mean(axis=0)
        return float(mean[0]), float(mean[1])


def in_mission_frame(visit: PotVisit) -> tuple[float, float, float]:
    """Where the located pot stands in the mission's frame: its map position less the map's drift
    there. What the report's ``moved`` says and ``mission update`` writes, so the next patrol,
    whose map drifts alike, finds the pot where the mission now puts it."""
    x, y, facing = visit.located
    return x - visit.drift[0], y - visit.drift[1], facing
