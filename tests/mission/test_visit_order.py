"""The order a patrol visits its pots in: as listed, greedy nearest-first, or the shortest tour
over path lengths (ending at home)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mission.patrol.mission_file import mission_from_world, parse_mission
from mission.patrol.visit_order import straight_lines, visit_order
from nav.tour import tour_length
from sim.generate import generate_world

def test_nearest_first_is_greedy_between_approach_poses():
    pots = [{"id": "far", "x": 5.0, "y": 1.0, "facing": -math.pi / 2},
            {"id": "near", "x": 1.0, "y": 1.0, "facing": -math.pi / 2},
            {"id": "mid", "x": 3.0, "y": 1.0, "facing": -math.pi / 2},
            {"id": "twin", "x": 3.0, "y": 0.0, "facing": math.pi / 2}]  # same approach pose as mid
    m = parse_mission({"name": "n", "order": "nearest", "pots": pots}, "m.yaml")
    assert [p.id for p in visit_order(m, (0.0, 0.5))] == ["near", "mid", "twin", "far"]
    listed = m.model_copy(update={"order": "as_listed"})
    assert [p.id for p in visit_order(listed, (0.0, 0.5))] == ["far", "near", "mid", "twin"]


def test_nearest_first_measures_to_approach_poses_not_pot_centres():
    pots = [{"id": "A", "x": 1.0, "y": 0.0, "facing": 0.0},  # centre 1.0 away, approach (1.5, 0): 1.5
            {"id": "B", "x": 1.2, "y": 0.0, "facing": math.pi}]  # centre 1.2 away, approach (0.7, 0): 0.7
    m = parse_mission({"name": "n", "order": "nearest", "pots": pots}, "m.yaml")
    assert [p.id for p in visit_order(m, (0.0, 0.0))] == ["B", "A"]


def _length(m, order, start=(0.0, 0.0)):
    pts = [start, *(m.approach(p)[:2] for p in order)] + ([(m.home.x, m.home.y)] if m.return_home else [])
    return tour_length(straight_lines(np.array(pts)), list(range(len(pts))))


def test_shortest_is_never_longer_than_nearest_on_generated_worlds():
    for seed, (rows, per_row, bays) in enumerate([(3, 4, 1), (6, 14, 1), (6, 15, 2), (4, 6, 3), (2, 10, 1)], 1):
        m = mission_from_world(generate_world(rows, per_row, seed, bays=bays))
        assert m.order == "shortest"  # what from-world writes
        shortest = visit_order(m, (0.0, 0.0))
        nearest = visit_order(m.model_copy(update={"order": "nearest"}), (0.0, 0.0))
        assert sorted(p.id for p in shortest) == sorted(p.id for p in m.pots)
        assert _length(m, shortest) <= _length(m, nearest) + 1e-9
        assert _length(m, shortest) < _length(m.model_copy(update={"order": "as_listed"}), m.pots)


def test_shortest_drives_each_aisle_once_in_a_row_of_pots():
    """Two rows facing one aisle, listed zig-zag across it: the tour sweeps the aisle out and
    comes back, the length of the aisle twice, not once per pot."""
    pots = [{"id": f"{side}{k}", "x": 1.0 + k, "y": y, "facing": facing}
            for k in range(8) for side, y, facing in (("S", 0.0, math.pi / 2), ("N", 2.0, -math.pi / 2))]
    m = parse_mission({"name": "aisle", "order": "shortest", "pots": pots}, "m.yaml")
    order = [p.id for p in visit_order(m, (0.0, 1.0))]
    xs = [int(i[1:]) for i in order]
    turns = sum(1 for a, b, c in zip(xs, xs[1:], xs[2:]) if (b - a) * (c - b) < 0)
    best = 2 * math.hypot(1.0, 0.5) + 7.0 + 1.0 + 7.0  # in, out along one side, across, back, home
    assert turns <= 1 and _length(m, visit_order(m, (0.0, 1.0)), (0.0, 1.0)) == pytest.approx(best)


def test_shortest_orders_by_the_lengths_it_is_given():
    """A wall between two pots (the lengths say so) changes the order straight lines would pick."""
    pots = [{"id": "A", "x": 1.0, "y": 0.0, "facing": math.pi}, {"id": "B", "x": 3.0, "y": 0.0, "facing": math.pi},
            {"id": "C", "x": 2.0, "y": 3.0, "facing": math.pi}]
    m = parse_mission({"name": "w", "order": "shortest", "return_home": False, "pots": pots}, "m.yaml")
    assert [p.id for p in visit_order(m, (0.0, 0.0))] == ["A", "B", "C"]

    def walled(points):  # A and B far apart by path, C near both
        d = straight_lines(points)
        d[1, 2] = d[2, 1] = 50.0
        return d

    assert [p.id for p in visit_order(m, (0.0, 0.0), walled)] == ["A", "C", "B"]
