"""The planner's path lengths between many points: straight where the way is open, round a wall
where it is not, open across unknown ground and beyond the costmap, infinite when walled in."""
from __future__ import annotations

import numpy as np
import pytest

from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.costmap.inflation import InflationLayer
from nav.path_lengths import path_lengths


def room(value=FREE):
    return CostGrid(np.full((200, 200), value, np.uint8), 0.05, 0.0, 0.0)  # 10 x 10 m


def test_open_floor_lengths_are_straight_lines_to_a_coarse_cell():
    pts = np.array([[1.0, 1.0], [9.0, 1.0], [9.0, 9.0], [5.0, 5.0]])
    d = path_lengths(room(), pts)
    straight = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))
    assert np.allclose(d, d.T) and np.all(np.diag(d) == 0)
    assert np.all(np.abs(d - straight) <= 0.02 * straight + 0.4)


def test_a_wall_makes_the_way_round_it():
    """A 0.1 m wall as the costmap holds it (inflated: 0.54 m the robot cannot cross) is closed
    to the coarse cells too, however it lies across them."""
    g = room()
    g.data[:180, 98:100] = LETHAL  # a wall up the middle with a gap at the top
    g.data[:] = InflationLayer(0.05, 0.22, 0.25, 5.0).apply(g.data)
    d = path_lengths(g, np.array([[4.0, 1.0], [6.0, 1.0]]))
    assert d[0, 1] == pytest.approx(2 * np.hypot(1.0, 8.5), rel=0.05)  # up through the gap (9..10 m) and down


def test_unknown_ground_and_points_off_the_costmap_count_as_open():
    d = path_lengths(room(UNKNOWN), np.array([[1.0, 1.0], [30.0, 1.0]]))
    assert d[0, 1] == pytest.approx(29.0, abs=0.4)


def test_a_point_walled_in_is_unreachable():
    g = room()
    g.data[80:120, 80:84] = g.data[80:120, 116:120] = LETHAL
    g.data[80:84, 80:120] = g.data[116:120, 80:120] = LETHAL
    d = path_lengths(g, np.array([[1.0, 1.0], [5.0, 5.0]]))
    assert np.isinf(d[0, 1]) and np.isinf(d[1, 0])
