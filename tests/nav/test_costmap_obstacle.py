"""The obstacle layer and its ray tracing: marking, clearing, ranges, garbage."""
from __future__ import annotations

import numpy as np
import pytest

from hw.interfaces import LidarScan
from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.costmap.obstacle import ObstacleLayer
from nav.costmap.raytrace import clear_rays, ray_cells
from tests.nav.builders import box_occupancy, scan_from_occupancy


def layer(default=UNKNOWN, size=(80, 80), mark=5.0, clear=12.0, inf_is_valid=False, min_range=0.25) -> ObstacleLayer:
    grid = CostGrid.filled(size[1], size[0], 0.05, 0.0, 0.0, default)
    return ObstacleLayer(grid, min_range, mark, clear, inf_is_valid)


def beams(*pairs) -> LidarScan:
    a, r = zip(*pairs)
    return LidarScan(0.0, np.array(a, np.float32), np.array(r, np.float32))


def test_a_scan_marks_the_box_and_clears_the_way_to_it():
    occ = box_occupancy()  # occupied x 2.5..2.75 m, y 1.5..2.5 m
    ob = layer()
    pose = (1.0, 2.0, 0.0)
    ob.update(scan_from_occupancy(occ, 0.05, pose), pose)
    d = ob.grid.data
    assert d[40, 50] == LETHAL  # the box face straight ahead
    assert np.all(d[40, 21:50] == FREE)  # the beam's way to it
    assert d[40, 52] == UNKNOWN  # behind the face: never seen
    assert not np.any(d[occ == 0] == LETHAL)  # marks only where something is


def test_returns_closer_than_min_range_are_dropped_everywhere():
    ob = layer()
    ob.update(beams((0.0, 0.10), (np.pi / 2, 0.24)), (2.0, 2.0, 0.0))
    assert np.all(ob.grid.data == UNKNOWN)  # neither marked nor cleared


def test_marking_stops_at_obstacle_max_range_but_clearing_goes_on():
    ob = layer(default=FREE, mark=2.5, clear=3.0)
    ob.grid.data[40, 50] = LETHAL  # an old obstacle at 2.0 m along the beam, now gone
    ob.update(beams((0.0, 2.7)), (0.0 + 0.025, 2.025, 0.0))
    assert ob.grid.data[40, 40] == FREE
    assert not np.any(ob.grid.data == LETHAL)  # 2.7 m > 2.5 m: not marked


def test_clearing_stops_at_raytrace_max_range():
    ob = layer(mark=2.5, clear=3.0)
    ob.update(beams((0.0, 3.5)), (0.025, 2.025, 0.0))
    row = ob.grid.data[40]
    assert np.all(row[:61] == FREE) and np.all(row[61:] == UNKNOWN)  # 3.0 m = 60 cells past the sensor


def test_beams_without_return_clear_only_when_inf_is_valid():
    for valid, expect in ((False, UNKNOWN), (True, FREE)):
        ob = layer(clear=2.0, inf_is_valid=valid)
        ob.update(beams((0.0, np.inf)), (0.025, 2.025, 0.0))
        assert ob.grid.data[40, 30] == expect
        assert not np.any(ob.grid.data == LETHAL)


def test_a_beam_of_the_same_scan_never_erases_a_mark():
    ob = layer()
    # beam 1 hits (2.0, 2.0) head on; beam 2 grazes past that cell towards a farther return
    ob.update(beams((0.0, 1.0), (0.0005, 2.0)), (1.025, 2.025, 0.0))
    assert ob.grid.data[40, 40] == LETHAL


def test_garbage_ranges_do_not_raise():
    ob = layer()
    ob.update(beams((0.0, np.nan), (0.5, -1.0), (np.nan, 1.0), (1.0, 1.0)), (2.0, 2.0, 0.0))
    assert (ob.grid.data == LETHAL).sum() == 1


def test_a_sensor_outside_the_grid_changes_nothing():
    ob = layer()
    ob.update(beams((0.0, 1.0)), (-1.0, 2.0, 0.0))
    assert np.all(ob.grid.data == UNKNOWN)


def test_beams_leaving_the_grid_are_clipped_at_its_edge():
    ob = layer(size=(20, 20))
    ob.update(LidarScan(0.0, np.linspace(-np.pi, np.pi, 720, endpoint=False).astype(np.float32),
                        np.full(720, 5.0, np.float32)), (0.5, 0.5, 0.3))
    assert np.all(ob.grid.data[[0, -1], :] == FREE) and np.all(ob.grid.data[:, [0, -1]] == FREE)


@pytest.mark.parametrize("seed", range(3))
def test_numba_and_numpy_ray_tracing_visit_the_same_cells(seed):
    rng = np.random.default_rng(seed)
    x0, y0 = 40, 37
    x1, y1 = rng.integers(0, 80, 300), rng.integers(0, 80, 300)
    x1[:3], y1[:3] = [x0, x0 + 7, x0], [y0, y0, y0 - 9]  # a point, and axis-aligned rays
    a = np.zeros((80, 80), np.uint8)
    clear_rays(a, x0, y0, x1, y1, 1)
    b = np.zeros((80, 80), np.uint8)
    ix, iy = ray_cells(x0, y0, x1, y1)
    b[iy, ix] = 1
    assert np.array_equal(a, b)
    # Each ray is 8-connected, runs from start to end cell, and has one cell per major-axis step.
    ix, iy = ray_cells(x0, y0, x1[3:4], y1[3:4])
    assert (ix[0], iy[0], ix[-1], iy[-1]) == (x0, y0, x1[3], y1[3])
    assert np.all(np.maximum(np.abs(np.diff(ix)), np.abs(np.diff(iy))) == 1)
