"""Incremental costmap updates for consumers (seed: always_send_full_costmap False).

The seed publishes changed regions instead of the whole grid every cycle: a full-grid publish
serialised tens of thousands of cells on the Pi every update, changed or not, and cutting it was
one of the two bandwidth levers that kept the link alive. Here a costmap keeps a version number
that moves whenever its grid changes and a short log of which 16 x 16-cell tiles each version
touched. ``changes_since(v)`` answers with the tiles changed after version ``v``, cut from the
current grid and merged into row runs, so applying them to a copy taken at ``v`` reproduces the
grid exactly. A consumer further behind than the log, or across a change of extent or origin (a
rolling window that moved), gets one full-grid region instead.
"""
from __future__ import annotations

from collections import deque
from typing import NamedTuple

import numpy as np

from nav.costmap.grid import CostGrid

TILE = 16
"""Tile edge in cells (0.8 m at 0.05 m): small enough that a scan's changes stay local."""
HISTORY = 64
"""Versions remembered (13 s of the local map at 5 Hz); older consumers get the full grid."""

Region = tuple[int, int, np.ndarray]
"""(ix0, iy0, block): ``block`` (uint8 [rows, cols]) replaces the cells from (ix0, iy0) on."""


class Changes(NamedTuple):
    version: int
    """The version the consumer has once it applied ``regions``."""
    regions: list[Region]
    full: bool
    """True when ``regions`` is the whole grid (origin or extent may have changed)."""
    origin: tuple[float, float]
    """The grid's origin at ``version``."""


class ChangeLog:
    def __init__(self):
        self.version = 0
        self._log: deque[tuple[int, np.ndarray | None]] = deque(maxlen=HISTORY)
        """(version, dirty-tile mask or None for 'everything')."""

    def record(self, old: CostGrid, new: CostGrid) -> None:
        """Note what changed from ``old`` to ``new``; the version moves only if something did."""
        if old.data.shape != new.data.shape or (old.origin_x, old.origin_y) != (new.origin_x, new.origin_y):
            self.version += 1
            self._log.append((self.version, None))
            return
        tiles = dirty_tiles(old.data != new.data)
        if tiles.any():
            self.version += 1
            self._log.append((self.version, tiles))

    def since(self, version: int, grid: CostGrid) -> Changes:
        origin = (grid.origin_x, grid.origin_y)
        if version == self.version:
            return Changes(self.version, [], False, origin)
        oldest = self._log[0][0] if self._log else self.version + 1
        newer = [mask for v, mask in self._log if v > version]
        if version > self.version or version < oldest - 1 or any(m is None for m in newer):
            return Changes(self.version, [(0, 0, grid.data.copy())], True, origin)
        return Changes(self.version, regions(np.logical_or.reduce(newer), grid.data), False, origin)


def dirty_tiles(changed: np.ndarray) -> np.ndarray:
    """bool [tiles_y, tiles_x]: which TILE x TILE tiles contain a changed cell."""
    h, w = changed.shape
    ty, tx = -(-h // TILE), -(-w // TILE)
    padded = np.zeros((ty * TILE, tx * TILE), dtype=bool)
    padded[:h, :w] = changed
    return padded.reshape(ty, TILE, tx, TILE).any(axis=(1, 3))


def regions(tiles: np.ndarray, data: np.ndarray) -> list[Region]:
    """Runs of dirty tiles along each tile row, cut from ``data``."""
    out = []
    edges = np.diff(np.pad(tiles.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    for ty, tx0 in zip(*np.nonzero(edges == 1)):
        tx1 = tx0 + int(np.argmax(edges[ty, tx0 + 1:] == -1)) + 1
        y0, x0 = ty * TILE, tx0 * TILE
        out.append((int(x0), int(y0), data[y0:y0 + TILE, x0:tx1 * TILE].copy()))
    return out


def apply_changes(grid: CostGrid | None, changes: Changes, resolution: float) -> CostGrid:
    """A consumer's side: ``grid`` (its copy at an older version, or None) brought up to date."""
    if changes.full or grid is None:
        if not changes.full:
            raise ValueError("a consumer without a grid needs the full grid: ask changes_since(-1)")
        return CostGrid(changes.regions[0][2].copy(), resolution, *changes.origin)
    out = grid.copy()
    for x0, y0, block in changes.regions:
        out.data[y0:y0 + block.shape[0], x0:x0 + block.shape[1]] = block
    return out
