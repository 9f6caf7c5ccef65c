"""The static layer: map_server trinary thresholds and sampling a map onto the costmap."""
from __future__ import annotations

import numpy as np

from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.costmap.static import StaticLayer


def test_trinary_thresholds_follow_map_server():
    st = StaticLayer(0.25, 0.65, track_unknown_space=True)
    occ = np.array([[0, 25, 26, 64, 65, 100, -1, 101]], np.int16)
    assert st.trinary(occ).tolist() == [[FREE, FREE, UNKNOWN, UNKNOWN, LETHAL, LETHAL, UNKNOWN, UNKNOWN]]
    untracked = StaticLayer(0.25, 0.65, track_unknown_space=False)
    assert untracked.trinary(np.array([[-1, 50]], np.int8)).tolist() == [[FREE, FREE]]


def test_an_aligned_map_is_copied_into_place_and_the_rest_is_unknown():
    target = CostGrid.filled(40, 30, 0.05, -1.0, -0.5, UNKNOWN)
    occ = np.zeros((10, 20), np.int8)
    occ[3, 5] = 100
    occ[0, 0] = -1
    st = StaticLayer(0.25, 0.65, True)
    st.set_map(occ, 0.05, 0.0, 0.0, target)  # the map's corner is costmap cell (20, 10)
    c = st.costs
    assert c.shape == (30, 40)
    assert c[10 + 3, 20 + 5] == LETHAL and c[10, 20] == UNKNOWN
    assert (c[10:20, 20:40] == FREE).sum() == 200 - 2
    assert np.all(c[:10] == UNKNOWN) and np.all(c[:, :20] == UNKNOWN) and np.all(c[20:] == UNKNOWN)


def test_a_coarser_map_covers_several_costmap_cells_per_map_cell():
    target = CostGrid.filled(8, 8, 0.05, 0.0, 0.0, UNKNOWN)
    occ = np.zeros((4, 4), np.int8)
    occ[1, 2] = 100
    st = StaticLayer(0.25, 0.65, True)
    st.set_map(occ, 0.10, 0.0, 0.0, target)
    lethal = np.argwhere(st.costs == LETHAL)
    assert sorted(map(tuple, lethal)) == [(2, 4), (2, 5), (3, 4), (3, 5)]
