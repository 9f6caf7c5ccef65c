"""The fleet's split (fleet/split.py) on a greenhouse of straight aisles: a pot's path length to
another in its aisle is along the aisle; to one in another aisle, out by the nearer end, along
the headland and in (what the planner's path lengths give in a row greenhouse)."""
from __future__ import annotations

import numpy as np

from fleet.split import NO_AISLE, PER_POT_M, split_pots
from nav.tour import shortest_tour, tour_length

LENGTH = 10.0
"""Aisle length, m; the headlands run along x = 0 and x = LENGTH."""


def greenhouse(aisles: int, pots_per_aisle: int, spacing: float = 1.0):
    """Pots (x, aisle y) on a grid, their aisle labels and the lengths between them."""
    xs = np.linspace(1.0, LENGTH - 1.0, pots_per_aisle)
    pts = np.array([(x, a * spacing) for a in range(aisles) for x in xs])
    labels = np.repeat(np.arange(aisles), pots_per_aisle)
    return pts, labels, lengths(pts, pts)


def lengths(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    x1, y1 = a[:, None, 0], a[:, None, 1]
    x2, y2 = b[None, :, 0], b[None, :, 1]
    around = np.minimum(x1 + x2, 2 * LENGTH - x1 - x2) + np.abs(y1 - y2)
    return np.where(np.isclose(y1, y2), np.abs(x1 - x2), around)


def from_docks(pts: np.ndarray, docks: dict[str, tuple[float, float]]) -> dict[str, np.ndarray]:
    return {r: lengths(np.array([d]), pts)[0] for r, d in docks.items()}


def one_robot_length(pts, between, fd) -> float:
    m = np.zeros((len(pts) + 1,) * 2)
    m[0, 1:] = m[1:, 0] = fd
    m[1:, 1:] = between
    order = shortest_tour(np.pad(m, ((0, 1), (0, 1)), mode="edge"), 0, len(pts) + 1)
    return tour_length(m, [0, *order, 0])


def test_two_docks_at_either_end_each_take_their_near_half_and_no_aisle_is_split():
    pts, labels, between = greenhouse(aisles=6, pots_per_aisle=5)
    docks = {"r1": (0.0, -0.5), "r2": (0.0, 5.5)}
    s = split_pots(between, from_docks(pts, docks), labels)
    assert sorted(s.parts["r1"] + s.parts["r2"]) == list(range(len(pts)))
    assert set(labels[s.parts["r1"]]) == {0, 1, 2} and set(labels[s.parts["r2"]]) == {3, 4, 5}
    assert abs(s.lengths["r1"] - s.lengths["r2"]) < 1e-6  # the mirror image
    alone = one_robot_length(pts, between, from_docks(pts, {"r": docks["r1"]})["r"])
    assert max(s.lengths.values()) < 0.6 * alone


def test_three_robots_from_one_end_bring_the_last_home_sooner_than_two():
    pts, labels, between = greenhouse(aisles=6, pots_per_aisle=5)
    docks = {"r1": (0.0, -0.5), "r2": (0.0, 2.5), "r3": (0.0, 5.5)}
    fd = from_docks(pts, docks)
    two = split_pots(between, fd, labels, up=["r1", "r3"])
    three = split_pots(between, fd, labels)
    assert three.makespan < two.makespan
    assert all(three.parts[r] for r in docks)


def test_an_aisle_is_split_only_when_that_saves_more_than_keep_whole():
    # one aisle, a robot at each end: split, each does its half and is home in 53 % of the time
    pts, labels, between = greenhouse(aisles=1, pots_per_aisle=16)
    fd = from_docks(pts, {"r1": (0.0, 0.0), "r2": (LENGTH, 0.0)})
    whole = split_pots(between, fd, labels, keep_whole=1.0)
    assert sorted(len(o) for o in whole.parts.values()) == [0, 16]
    cut = split_pots(between, fd, labels, keep_whole=0.0)
    assert sorted(len(o) for o in cut.parts.values()) == [8, 8]
    saved = 1.0 - cut.makespan / whole.makespan
    assert 0.45 < saved < 0.50
    # but the halves would take turns at the aisle's lock: counting that wait, the cut saves
    # almost nothing, so any margin keeps the aisle whole
    assert split_pots(between, fd, labels, keep_whole=0.01).parts == whole.parts
    assert split_pots(between, fd, labels).parts == whole.parts
    # four aisles, two robots from one end: two whole aisles each
    pts, labels, between = greenhouse(aisles=4, pots_per_aisle=5)
    s = split_pots(between, from_docks(pts, {"r1": (0.0, -0.5), "r2": (0.0, 3.5)}), labels)
    assert {r: sorted(set(labels[o].tolist())) for r, o in s.parts.items()} == {"r1": [0, 1], "r2": [2, 3]}


def test_a_robot_down_gets_nothing_and_the_others_take_every_pot():
    pts, labels, between = greenhouse(aisles=4, pots_per_aisle=4)
    fd = from_docks(pts, {"r1": (0.0, -0.5), "r2": (0.0, 1.5), "r3": (0.0, 3.5)})
    s = split_pots(between, fd, labels, up=["r1", "r3"])
    assert set(s.parts) == {"r1", "r3"}
    assert sorted(s.parts["r1"] + s.parts["r3"]) == list(range(len(pts)))


def test_pots_in_no_aisle_are_shared_one_by_one():
    pts = np.array([(1.0, 0.0), (2.0, 0.0), (8.0, 0.0), (9.0, 0.0)])
    between = np.abs(pts[:, None, 0] - pts[None, :, 0])
    fd = {"r1": np.abs(pts[:, 0] - 0.0), "r2": np.abs(pts[:, 0] - 10.0)}
    s = split_pots(between, fd, [NO_AISLE] * 4)
    assert sorted(s.parts["r1"]) == [0, 1] and sorted(s.parts["r2"]) == [2, 3]
    assert s.lengths == {"r1": 4.0, "r2": 4.0}


def test_on_the_planners_path_lengths_two_docks_at_either_end_of_a_greenhouse_split_by_aisles():
    """The tiny greenhouse's map as the planner sees it (inflated costmap, nav.path_lengths),
    its aisles from the map (fleet.aisles): a robot at the south-west corner and one at the
    north-east each take the aisles near them, whole."""
    from fleet.aisles import find_aisles
    from nav.occupancy import OccupancyMap
    from nav.path_lengths import lengths_from, path_lengths
    from tests.nav.builders import RES, greenhouse_grid, greenhouse_occupancy

    rows_y, pots_x = (1.0, 2.0, 3.0), (2.0, 3.0, 4.0, 5.0)
    pots = np.array([(x, y, np.pi / 2 if y == 2.0 else -np.pi / 2) for y in rows_y for x in pots_x])
    approach = pots[:, :2] + 0.5 * np.c_[np.cos(pots[:, 2]), np.sin(pots[:, 2])]
    aisles = find_aisles(OccupancyMap(greenhouse_occupancy(), RES, 0.0, 0.0), pots).at(approach[:, 0], approach[:, 1])
    grid = greenhouse_grid()
    docks = {"r1": (1.0, 0.5), "r2": (6.0, 3.5)}
    fd = {r: lengths_from(grid, d, approach) for r, d in docks.items()}
    s = split_pots(path_lengths(grid, approach), fd, aisles, per_pot=0.0)  # driving alone
    assert sorted(s.parts["r1"] + s.parts["r2"]) == list(range(12))
    assert set(aisles[s.parts["r1"]]).isdisjoint(aisles[s.parts["r2"]])  # no aisle shared
    south = aisles[0]  # the south row's aisle goes to the robot docked at its end
    assert south in aisles[s.parts["r1"]] and aisles[11] in aisles[s.parts["r2"]]
    alone = split_pots(path_lengths(grid, approach), {"r1": fd["r1"]}, aisles, per_pot=0.0)
    assert s.makespan < 0.8 * alone.makespan  # 4 m aisles: the drive to the aisles is most of a tour
    # with each pot's stop counted, sharing the middle aisle's eight pots would balance the stops,
    # but the two would take turns at its lock: the aisle stays whole
    stops = split_pots(path_lengths(grid, approach), fd, aisles)
    assert sorted(len(o) for o in stops.parts.values()) == [4, 8]
    assert set(aisles[stops.parts["r1"]]).isdisjoint(aisles[stops.parts["r2"]])
    shared = split_pots(path_lengths(grid, approach), fd, aisles, keep_whole=-1.0)  # the waits priced, any gain taken
    assert sorted(len(o) for o in shared.parts.values()) == [6, 6] and shared.makespan < stops.makespan


def test_twelve_aisles_two_or_three_robots_split_into_near_equal_blocks():
    pts, labels, between = greenhouse(aisles=12, pots_per_aisle=15)
    two = split_pots(between, from_docks(pts, {"r1": (0.0, -0.5), "r2": (0.0, 11.5)}), labels)
    assert {r: sorted(set(labels[o].tolist())) for r, o in two.parts.items()} == {"r1": list(range(6)),
                                                                                    "r2": list(range(6, 12))}
    docks = {"r1": (0.0, -0.5), "r2": (0.0, 5.5), "r3": (0.0, 11.5)}
    three = split_pots(between, from_docks(pts, docks), labels)
    alone = split_pots(between, from_docks(pts, {"r1": docks["r1"]}), labels)
    assert three.makespan <= 0.36 * alone.makespan and max(three.lengths.values()) - min(three.lengths.values()) < 2.0
