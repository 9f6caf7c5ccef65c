"""Where a robot that cannot reach its dock stops (issue 31 item 3): out of the aisles and
clear of their mouths.

A robot whose pack will not take it home must not die where it blocks the way: in an aisle
between rows, or at an aisle's mouth, people with carts would have to push it aside. It
drives instead to the nearest place (by the planner's path length) that is

- open ground: a disk of ``OPEN_RADIUS`` fits round it in free space (a cross aisle, the floor
  by the dock), which no 0.8 m aisle between rows allows (spec/world.md: aisles ~0.8 m);
- at least ``MOUTH_KEEP`` from every aisle cell, so the mouths stay clear;
- with ``WALL_KEEP`` between its centre and anything (the robot fits, off the wall).

The map is the global costmap (0.05 m cells); unknown ground is not a place to stop.
"""
from __future__ import annotations

from typing import Callable

import cv2
import numpy as np

from nav.costmap.grid import INSCRIBED, CostGrid

OPEN_RADIUS = 0.5
"""A passage narrower than twice this is an aisle, m (aisles between rows are ~0.8 m)."""
MOUTH_KEEP = 1.2
"""Distance kept from every aisle cell, m (an aisle cell is where the open disk no longer fits,
~0.15 m inside the rows' ends): in a 1.9 m cross aisle the robot then stands against the far
wall, leaving ~0.9 m in front of the mouth for a person or a cart to turn in."""
WALL_KEEP = 0.35
"""Distance from the spot to the nearest obstacle, m: the robot's 0.25 m radius and a margin."""
STRIDE = 4
"""Candidate spots are every STRIDE-th cell each way (0.2 m): path lengths to all of them cost
one wavefront."""


def _disk(radius_cells: float) -> np.ndarray:
    r = max(1, int(round(radius_cells)))
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))


def clear_spots(grid: CostGrid) -> np.ndarray:
    """(N, 2) world points where a stopped robot blocks no aisle."""
    res = grid.geometry.resolution
    free = (grid.data < INSCRIBED).astype(np.uint8)
    opened = cv2.morphologyEx(free, cv2.MORPH_OPEN, _disk(OPEN_RADIUS / res))
    aisles = (free & (1 - opened)).astype(np.uint8)
    near_mouth = cv2.dilate(aisles, _disk(MOUTH_KEEP / res)) > 0
    clearance = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * res
    ok = (opened > 0) & ~near_mouth & (clearance >= WALL_KEEP)
    ok[1::STRIDE] = ok[2::STRIDE] = ok[3::STRIDE] = False
    ok[:, 1::STRIDE] = ok[:, 2::STRIDE] = ok[:, 3::STRIDE] = False
    iy, ix = np.nonzero(ok)
    x, y = grid.geometry.centre_of(ix, iy)
    return np.column_stack([x, y])


def parking_spot(grid: CostGrid, here: tuple[float, float],
                 lengths: Callable[[tuple[float, float], np.ndarray], np.ndarray]) -> tuple[float, float, float] | None:
    """The nearest clear spot by path from ``here``: (x, y, metres to it); None when there is none."""
    spots = clear_spots(grid)
    if not len(spots):
        return None
    metres = lengths(here, spots)
    k = int(np.argmin(metres))
    return (float(spots[k, 0]), float(spots[k, 1]), float(metres[k])) if np.isfinite(metres[k]) else None
