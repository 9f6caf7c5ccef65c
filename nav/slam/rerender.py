"""A pose-graph correction reaches the map without stopping the scan loop (issue 30, item 4).

A solve moves keyframes, and the grid must follow: the region the moved scans reach (at their
old poses and their new) is cleared and drawn again from every kept scan that touches it, each
confined to it, so the cells outside keep what they had and nothing is counted twice. At the
end of the 180-pot patrol that is ~2,000 kept scans, 0.9-1.1 s drawn in one go; on the robot
the free-running worker dropped every scan meanwhile, and the robot drove on wheel odometry.

So the region is drawn into a grid of its own (the *shadow*), ``BUDGET`` kept scans for each
scan the worker maps, while the live grid goes on taking every scan as before; scans kept in
the meantime join the queue, so the shadow sees the same scans in the same order a drawing in
one go followed by live updates would. When the queue is empty the shadow replaces the region's
cells in the live grid at once: the map handed out is the old one until then and the moved one
after, never a region half drawn at new poses and half at old. (Non-kept scans that fall in
the window meanwhile are dropped from it, as the drawing in one go drops them: the kept scans,
one every 0.2 m, are what the map is made of.)

The scan whose keyframe solved the graph draws none (the solve, ~60 ms for 1,250 keyframes, and
the loop match are its work); the next ones draw ``BUDGET`` each. Only a caller that asks for the
whole map to keep (``Mapper.settle``: the patrol's end, a map save) has the rest drawn at once.

A second solve before the first is drawn restarts the drawing over both regions (the shadow's
scans were drawn at poses that just moved again); loop closures come at least ``LOOP_GAP``
of travel apart, so a drawing of ~2,000 scans (~50 scans, 5 s) is seldom restarted.

Measured on the scans of a recorded 180-pot patrol with 42 loop closures and 10 solves (CPU per
scan, in one process): drawn at once, the longest scan took 1,013 ms; drawn a share a scan, 136 ms
(a solve of 1,400 keyframes), median 1.73 -> 1.75 ms and p95 2.65 -> 2.81 ms (the 2 % of scans
carrying a share).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from nav.grid_geometry import GridGeometry
from nav.slam.grid import LogOddsGrid

BUDGET = 40
"""Kept scans drawn into the shadow per scan mapped. A kept scan costs 0.35-0.5 ms in a
greenhouse (a beam traced every half cell, up to 12 m), so the budget adds 15-20 ms to a scan,
well inside the 0.1 s scan period (a scan's own update is 1.4 ms median, 5.3 ms p95 on the
180-pot patrol), and the ~2,000 scans the patrol's closing loop moves are drawn in ~50 scans
(5 s of driving)."""


def region_of(geometry: GridGeometry, xy: np.ndarray, reach: np.ndarray) -> GridGeometry | None:
    """The cells within ``reach`` (N,) of the scans at ``xy`` (N, 2), clipped to the grid
    ``geometry``: a grid of its own on the same lattice (None when it misses the grid)."""
    (x0, y0), (x1, y1) = (xy - reach[:, None]).min(axis=0), (xy + reach[:, None]).max(axis=0)
    return clipped(geometry, (x0, y0, x1, y1))


def clipped(geometry: GridGeometry, bounds: tuple[float, float, float, float]) -> GridGeometry | None:
    """The cells of ``geometry`` inside the world box ``bounds`` (x0, y0, x1, y1), or None."""
    x0, y0, x1, y1 = bounds
    (ix0, ix1), (iy0, iy1) = geometry.cell_of([x0 + 1e-9, x1 - 1e-9], [y0 + 1e-9, y1 - 1e-9])
    ix0, iy0 = max(int(ix0), 0), max(int(iy0), 0)
    ix1, iy1 = min(int(ix1) + 1, geometry.width), min(int(iy1) + 1, geometry.height)
    if ix0 >= ix1 or iy0 >= iy1:
        return None
    return geometry.cropped(ix0, iy0, ix1, iy1)


def union(a: GridGeometry, b: GridGeometry) -> GridGeometry:
    """The smallest grid on the lattice covering both (two regions of one live grid)."""
    x0, y0 = min(a.origin_x, b.origin_x), min(a.origin_y, b.origin_y)
    x1, y1 = max(a.extent[1], b.extent[1]), max(a.extent[3], b.extent[3])
    return GridGeometry.covering(x0, y0, x1, y1, a.resolution)


def touching(region: GridGeometry, xy: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Which scans at ``xy`` (N, 2) reaching ``reach`` (N,) may touch a cell of ``region``."""
    x0, x1, y0, y1 = region.extent
    return ((xy[:, 0] + reach >= x0) & (xy[:, 0] - reach <= x1) &
            (xy[:, 1] + reach >= y0) & (xy[:, 1] - reach <= y1))


@dataclass
class Rerender:
    """A region of the map being drawn again in the background."""

    region: GridGeometry
    """The cells drawn again, on the live grid's lattice (inside it: the live grid only grows)."""
    queue: list[int]
    """Kept scans still to draw, oldest first (indices into the mapper's kept scans)."""
    since: int = 0
    """The scan that started it (it draws none: the solve was its work)."""
    shadow: LogOddsGrid = field(init=False)
    drawn: int = 0
    """Kept scans drawn so far."""

    def __post_init__(self) -> None:
        self.shadow = LogOddsGrid(self.region)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """The region in world metres (x0, y0, x1, y1): what the checkpoint keeps of it."""
        x0, x1, y0, y1 = self.region.extent
        return x0, y0, x1, y1

    def step(self, draw: Callable[[LogOddsGrid, int], None], budget: int = BUDGET) -> int:
        """Draw the next ``budget`` queued scans (``draw(shadow, i)`` draws kept scan ``i``);
        returns how many were drawn."""
        now, self.queue = self.queue[:budget], self.queue[budget:]
        for i in now:
            draw(self.shadow, i)
        self.drawn += len(now)
        return len(now)

    @property
    def done(self) -> bool:
        return not self.queue
