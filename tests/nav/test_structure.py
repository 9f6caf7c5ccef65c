"""The map's structure (nav.structure): long components are walls, dividers and benches; for the
person tracker only their straight runs, so a worker crouching 5 cm from a divider is not taken
in with it."""
from __future__ import annotations

import numpy as np

from nav.occupancy import OccupancyMap
from nav.structure import long_components, straight_runs

RES = 0.05


def _map(*boxes: tuple[float, float, float, float]) -> OccupancyMap:
    """8 x 6 m, occupied in each (x0, y0, x1, y1) box."""
    occ = np.zeros((int(6 / RES), int(8 / RES)), np.int8)
    for x0, y0, x1, y1 in boxes:
        occ[int(y0 / RES):int(y1 / RES) + 1, int(x0 / RES):int(x1 / RES) + 1] = 100
    return OccupancyMap(occ, RES, 0.0, 0.0)


DIVIDER = (6.95, 1.2, 7.05, 5.8)
CROUCHING = ((6.3, 1.2, 6.35, 1.8), (6.3, 1.2, 6.9, 1.25))  # the faces the lidar sees, 5 cm off it
CART = ((2.0, 3.0, 3.2, 3.05), (2.0, 3.0, 2.05, 3.6))  # a 1.2 m cart seen corner-on


def at(mask: np.ndarray, x: float, y: float) -> bool:
    return bool(mask[int(y / RES), int(x / RES)])


def test_a_worker_crouching_against_a_divider_is_one_long_component_with_it_but_no_straight_run():
    m = _map(DIVIDER, *CROUCHING)
    merged = long_components(m, 1.7)
    assert at(merged, 7.0, 3.0) and at(merged, 6.3, 1.5)  # the divider took the worker in
    runs = long_components(m, 1.7, run=1.3)
    assert at(runs, 7.0, 3.0) and at(runs, 7.0, 1.3) and at(runs, 7.0, 5.7)  # the divider, end to end
    assert not at(runs, 6.3, 1.5) and not at(runs, 6.6, 1.2)  # not its neighbour


def test_a_cart_has_no_run_as_long_as_a_wall_and_nothing_comes_of_nothing():
    m = _map(*CART, (0.0, 0.0, 7.9, 0.05))
    runs = straight_runs(m.occupied(), RES, 1.3, 0.1)
    assert at(runs, 4.0, 0.0) and not at(runs, 2.6, 3.0) and not at(runs, 2.0, 3.3)
    assert not straight_runs(np.zeros((10, 10), bool), RES, 1.3, 0.1).any()
    again = straight_runs(m.occupied(), RES, 1.3, 0.1)
    assert np.array_equal(runs, again)  # the same map, the same runs
