"""Frontiers: where mapped floor meets unknown ground; the nearest by path, small shadows and
blocked ones left out, none once the floor is all seen."""
from __future__ import annotations

import numpy as np
import pytest

from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.frontiers import frontier_clusters, nearest_frontier
from nav.occupancy import OccupancyMap


def room() -> tuple[OccupancyMap, CostGrid]:
    """A 6 x 4 m map: the west 3 m seen (free, walls round it), a wall at x = 3 m with a gap
    at y 3..4 m, nothing seen east of it; one pot's shadow (3 unknown cells) in the seen part."""
    occ = np.full((80, 120), -1, np.int8)
    occ[:, :60] = 0
    occ[0, :60] = occ[-1, :60] = occ[:, 0] = 100
    occ[:60, 59] = 100  # the wall, open from y = 3 m
    occ[40, 30:33] = -1  # a shadow behind a pot
    cost = np.where(occ == 100, LETHAL, np.where(occ < 0, UNKNOWN, FREE)).astype(np.uint8)
    return OccupancyMap(occ, 0.05, 0.0, 0.0), CostGrid(cost, 0.05, 0.0, 0.0)


def test_frontiers_are_free_cells_next_to_unknown_and_shadows_are_not():
    occupancy, _ = room()
    big = frontier_clusters(occupancy, min_cells=10)
    assert len(big) == 1 and set(big[0][:, 0]) == {59}  # the gap's cells at x = 2.95 m
    assert {len(c) for c in frontier_clusters(occupancy, min_cells=1)} >= {8}  # the shadow's ring is small


def test_the_nearest_frontier_is_nearest_by_path_not_straight_line():
    occupancy, costmap = room()
    f = nearest_frontier(occupancy, costmap, (1.0, 0.5), min_cells=10)
    assert f is not None and f.x == pytest.approx(2.975) and f.y >= 3.0  # through the gap, not the wall
    assert f.path_cost > np.hypot(2.0, 2.5)


def test_a_blocked_frontier_is_left_out_and_a_map_all_seen_has_none():
    occupancy, costmap = room()
    f = nearest_frontier(occupancy, costmap, (1.0, 0.5), min_cells=10)
    assert nearest_frontier(occupancy, costmap, (1.0, 0.5), min_cells=10, blocked=[(f.x, f.y)], blocked_radius=1.5) is None
    seen = OccupancyMap(np.where(occupancy.occupancy < 0, 0, occupancy.occupancy).astype(np.int8), 0.05, 0.0, 0.0)
    assert nearest_frontier(seen, costmap, (1.0, 0.5), min_cells=10) is None
