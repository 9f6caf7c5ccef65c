"""The layered costmap: the local rolling window, the global map with its static layer,
and clearing."""
from __future__ import annotations

import numpy as np
import pytest

from hw.interfaces import LidarScan
from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import FREE, INSCRIBED, LETHAL, UNKNOWN
from nav.costmap.layered import global_costmap, local_costmap
from tests.nav.builders import greenhouse_occupancy, scan_from_occupancy

CFG = CostmapsConfig()
OCC = greenhouse_occupancy()  # 7 x 4 m, origin (0, 0)


def scan_at(x, y, yaw=0.0, beams=500):
    return scan_from_occupancy(OCC, 0.05, (x, y, yaw), beams=beams)


def test_factories_follow_the_seed():
    local, glob = local_costmap(CFG), global_costmap(CFG)
    assert local.grid.data.shape == (60, 60) and local.grid.resolution == 0.05  # 3 x 3 m
    assert np.all(local.grid.data == FREE)
    assert glob.grid.data.shape == (80, 80) and (glob.grid.origin_x, glob.grid.origin_y) == (-2.0, -2.0)
    assert np.all(glob.grid.data == UNKNOWN)  # the global map tracks unknown space; it grows (below)
    # the seed's ranges: local marks to 2.5 m and clears to 3.0 m, global 5.0 and 12.0, both drop < 0.25 m
    assert (local.obstacle.mark_range, local.obstacle.clear_range, local.obstacle.min_range) == (2.5, 3.0, 0.25)
    assert (glob.obstacle.mark_range, glob.obstacle.clear_range, glob.obstacle.min_range) == (5.0, 12.0, 0.25)


def test_the_global_map_marks_to_5_m_only():
    glob = global_costmap(CFG)
    glob.cover(0.0, 0.0, 7.0, 4.0)  # the greenhouse
    glob.update(scan_at(0.5, 2.5), (0.5, 2.5, 0.0), (0.5, 2.5))
    g = glob.grid
    # Down the middle aisle the east wall is 6.5 m away: its cells are not marked, but the beams
    # cleared the aisle out to it (clearing reaches 12 m).
    wall = g.cost_at(np.full(5, 6.97), np.linspace(2.45, 2.55, 5))
    assert not np.any(wall == LETHAL)
    assert g.cost_at(6.9, 2.5)[()] == FREE
    assert g.cost_at(0.02, 2.5)[()] == LETHAL  # the west wall, 0.5 m away


def test_the_local_window_is_centred_on_the_robot():
    local = local_costmap(CFG)
    local.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    g = local.grid
    assert g.origin_x == pytest.approx(-0.5) and g.origin_y == pytest.approx(-1.0)
    assert g.cost_at(1.0, 0.5)[()] == FREE
    assert g.cost_at(1.0, 0.02)[()] == LETHAL  # the south wall, 0.48 m away
    assert g.cost_at(1.0, 0.2)[()] == INSCRIBED  # 0.2 m from the wall cell
    assert g.cost_at(2.0, 0.92)[()] == LETHAL  # pot P01's south face, ~1.1 m away


def test_the_rolling_window_keeps_what_it_saw_in_world_coordinates():
    local = local_costmap(CFG)
    local.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    seen = local.grid.cost_at(2.0, 0.92)[()]
    empty = LidarScan(0.0, np.zeros(0, np.float32), np.zeros(0, np.float32))
    local.update(empty, (1.6, 0.5, 0.0), (1.6, 0.5))  # moved 0.6 m east, saw nothing new
    g = local.grid
    assert g.origin_x == pytest.approx(0.1)
    assert g.cost_at(2.0, 0.92)[()] == seen == LETHAL
    assert g.cost_at(2.9, 1.5)[()] == FREE  # newly exposed cells start free


def test_scans_uncover_unknown_space_in_the_global_map():
    glob = global_costmap(CFG)
    glob.cover(-1.0, -1.0, 7.0, 4.0)
    glob.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    g = glob.grid
    assert g.cost_at(1.0, 0.5)[()] == FREE
    assert g.cost_at(1.0, -0.5)[()] == UNKNOWN  # behind the south wall
    assert g.cost_at(6.5, 3.5)[()] == UNKNOWN  # beyond 5 m and behind the pots: unseen
    assert g.cost_at(1.0, 0.02)[()] == LETHAL


def test_the_static_map_sets_walls_scans_cannot_erase_and_scans_uncover_its_unknown():
    glob = global_costmap(CFG)
    occ = OCC.copy()
    occ[20:40, 100:120] = -1  # an unexplored patch (x 5..6, y 1..2) of the map
    glob.set_static(occ, 0.05, 0.0, 0.0)
    g = glob.grid
    assert g.cost_at(3.0, 1.0)[()] == LETHAL and g.cost_at(5.5, 1.5)[()] == UNKNOWN
    assert g.cost_at(-1.0, -1.0)[()] == UNKNOWN  # outside the map
    # A scan from where a (moved) pot no longer is: clearing cannot remove the map's pot...
    no_pot = OCC.copy()
    no_pot[OCC[:, :] == 100] = 0
    no_pot[0, :] = no_pot[-1, :] = no_pot[:, 0] = no_pot[:, -1] = 100
    glob.update(scan_from_occupancy(no_pot, 0.05, (4.5, 1.5, 0.0)), (4.5, 1.5, 0.0), (4.5, 1.5))
    g = glob.grid
    assert g.cost_at(4.0, 1.0)[()] == LETHAL
    # ...but what it observed in the unknown patch is known now.
    assert g.cost_at(5.5, 1.5)[()] == FREE


def test_clear_forgets_observations_but_keeps_the_map():
    glob = global_costmap(CFG)
    glob.set_static(OCC, 0.05, 0.0, 0.0)
    glob.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    box = OCC.copy()
    box[8:12, 40:44] = 100  # a box at (2.0..2.2, 0.4..0.6)
    glob.update(scan_from_occupancy(box, 0.05, (1.0, 0.5, 0.0)), (1.0, 0.5, 0.0), (1.0, 0.5))
    assert glob.grid.cost_at(2.01, 0.5)[()] == LETHAL
    glob.clear()
    assert glob.grid.cost_at(2.01, 0.5)[()] == FREE
    assert glob.grid.cost_at(3.0, 1.0)[()] == LETHAL
    local = local_costmap(CFG)
    local.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    local.clear()
    assert np.all(local.grid.data == FREE)
    with pytest.raises(ValueError, match="no static layer"):
        local.set_static(OCC, 0.05, 0.0, 0.0)


def test_the_global_map_grows_to_take_in_the_map_and_a_goal_and_keeps_what_it_saw():
    glob = global_costmap(CFG)
    glob.cover(0.0, 0.0, 2.0, 1.5)
    glob.update(scan_at(1.0, 0.5), (1.0, 0.5, 0.0), (1.0, 0.5))
    seen = glob.grid.cost_at([1.0, 0.5], [0.02, 0.5])
    assert seen.tolist() == [LETHAL, FREE]
    big = np.zeros((200, 1200), np.int8)  # a free 60 x 10 m map reaching far east of the dock
    big[100, 1100] = 100
    glob.set_static(big, 0.05, -2.0, -3.0)
    g = glob.grid
    x0, x1, y0, y1 = g.geometry.extent
    assert x0 <= -2.0 and x1 >= 58.0 and y0 <= -3.0 and y1 >= 7.0  # the whole map is in
    assert g.cost_at(-2.0 + 1100 * 0.05 + 0.025, -3.0 + 100 * 0.05 + 0.025)[()] == LETHAL
    assert glob.grid.cost_at([1.0, 0.5], [0.02, 0.5]).tolist() == [LETHAL, FREE]  # kept across the growth
    glob.cover(80.0, 30.0, 81.0, 31.0)  # a goal beyond the map: in, unknown
    assert glob.grid.cost_at(80.5, 30.5)[()] == UNKNOWN
    assert glob.grid.geometry.extent[0] <= -2.0
    before = glob.grid.geometry
    glob.cover(0.0, 0.0, 1.0, 1.0)  # inside: nothing changes, it never shrinks
    assert glob.grid.geometry == before


def test_the_rolling_window_does_not_grow():
    local = local_costmap(CFG)
    local.cover(0.0, 0.0, 10.0, 10.0)
    assert local.grid.data.shape == (60, 60)
