"""The map's structure and its odd blobs: a worker crouching against a divider is not the divider."""
from __future__ import annotations

import numpy as np

from nav.occupancy import OccupancyMap
from nav.structure import odd_blobs

RES = 0.05


def _map() -> tuple[OccupancyMap, np.ndarray]:
    """A 10 x 6 m floor: walls round it, a divider along x = 7, a row of 0.25 m pots along y = 4,
    and a crouching worker's outline (0.5 x 0.4 m) 5 cm from the divider, all as the map draws
    them (their outline cells occupied, the rest free)."""
    occ = np.zeros((120, 200), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    occ[10:100, 140] = 100                               # the divider, x = 7.0, y 0.5..5
    pots = np.array([(1.0 + k, 4.0) for k in range(5)])
    iy, ix = np.mgrid[0:120, 0:200]
    cx, cy = (ix + 0.5) * RES, (iy + 0.5) * RES
    for x, y in pots:
        ring = np.abs(np.hypot(cx - x, cy - y) - 0.12) < 0.03
        occ[ring] = 100
    worker = (cx > 6.5) & (cx < 6.95) & (cy > 1.3) & (cy < 1.7)
    edge = worker & ~((cx > 6.55) & (cx < 6.9) & (cy > 1.35) & (cy < 1.65))
    occ[edge] = 100
    return OccupancyMap(occ, RES, 0.0, 0.0), pots


def test_a_worker_against_a_divider_is_a_blob_and_nothing_else_is():
    grid, pots = _map()
    blobs = odd_blobs(grid, pots, pot_reach=0.25, run=1.3, max_extent=1.7, min_area=0.01)
    assert blobs, "the worker against the divider was taken for the divider"
    for x, y, r in blobs:  # in pieces, each on the worker's outline (x 6.5..6.95, y 1.3..1.7)
        assert 6.45 <= x <= 7.0 and 1.25 <= y <= 1.75
        assert r <= 0.25
    xs, ys = [x for x, _, _ in blobs], [y for _, y, _ in blobs]
    assert max(xs) - min(xs) >= 0.2 and max(ys) - min(ys) >= 0.15  # the whole outline, not a corner


def test_unknown_pots_are_blobs_known_ones_are_not():
    grid, pots = _map()
    blobs = odd_blobs(grid, pots[:2], pot_reach=0.25, run=1.3, max_extent=1.7, min_area=0.01)
    pots_seen = sorted({round(x) for x, y, _ in blobs if abs(y - 4.0) < 0.2})
    assert pots_seen == [3, 4, 5]
