"""The aisle map (fleet/aisles.py) on small occupancy grids: the tiny greenhouse's rows, a
doorway, an open room."""
from __future__ import annotations

import numpy as np

from fleet.aisles import NO_AISLE, find_aisles, rows
from nav.occupancy import OccupancyMap
from tests.nav.builders import RES, greenhouse_occupancy, straight_path

ROWS, POTS_X = (1.0, 2.0, 3.0), (2.0, 3.0, 4.0, 5.0)


def tiny_greenhouse():
    """The 7 x 4 m greenhouse: rows at y = 1, 2, 3 (facing south, north, south), 0.8 m aisles."""
    m = OccupancyMap(greenhouse_occupancy(rows=ROWS, pots_x=POTS_X), RES, 0.0, 0.0)
    pots = np.array([(x, y, np.pi / 2 if y == 2.0 else -np.pi / 2) for y in ROWS for x in POTS_X])
    return m, pots


def test_rows_join_side_by_side_pots_and_never_jump_to_the_next_row():
    _, pots = tiny_greenhouse()
    pairs, ends = rows(pots)
    assert pairs == [(r * 4 + k, r * 4 + k + 1) for r in range(3) for k in range(3)]
    assert sorted(i for i, _ in ends) == [0, 3, 4, 7, 8, 11]


def test_the_space_between_rows_and_the_strips_by_the_walls_are_aisles_the_cross_aisles_are_not():
    m, pots = tiny_greenhouse()
    a = find_aisles(m, pots)
    assert a.count == 4
    # every approach pose (0.5 m off the pot along its facing) lies in an aisle, the pair of rows
    # facing each other sharing one
    approach = pots[:, :2] + 0.5 * np.c_[np.cos(pots[:, 2]), np.sin(pots[:, 2])]
    got = a.at(approach[:, 0], approach[:, 1])
    assert (got != NO_AISLE).all()
    assert len(set(got[:4])) == 1 and set(got[4:8]) == set(got[8:]) and got[0] != got[4]
    assert a.at([1.0, 6.0, 3.5], [2.0, 2.0, 0.5]).tolist() == [NO_AISLE, NO_AISLE, int(got[0])]
    # a drive from the west cross aisle along the south strip and up the east one enters one aisle
    path = np.vstack([straight_path((1.0, 0.5), (6.0, 0.5)), straight_path((6.0, 0.5), (6.0, 3.5))])
    assert a.along(path) == [int(got[0])]


def test_without_the_pots_a_dotted_row_is_no_wall():
    m, _ = tiny_greenhouse()
    a = find_aisles(m)
    xs = np.array(POTS_X)
    assert (a.at(np.r_[xs, xs], np.r_[[1.5] * 4, [2.5] * 4]) == NO_AISLE).all()  # the aisles between rows are open
    assert (a.at(xs, [0.3] * 4) != NO_AISLE).all()  # only a pot 0.85 m from the wall is a narrow passage


def test_a_doorway_narrower_than_two_robots_is_an_aisle_and_an_open_room_has_none():
    occ = np.zeros((60, 120), np.int8)  # 6 x 3 m
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    m = OccupancyMap(occ.copy(), RES, 0.0, 0.0)
    assert find_aisles(m).count == 0
    occ[:, 60:62] = 100  # a wall across at x = 3 m ...
    occ[20:34, 60:62] = 0  # ... with a 0.7 m doorway
    a = find_aisles(OccupancyMap(occ, RES, 0.0, 0.0))
    assert a.count == 1
    assert a.at([3.05, 1.0, 5.0], [1.35, 1.35, 1.35]).tolist() == [0, NO_AISLE, NO_AISLE]
    occ[14:40, 60:62] = 0  # widened to 1.3 m: two robots pass
    assert find_aisles(OccupancyMap(occ, RES, 0.0, 0.0)).count == 0


def world_occupancy(world) -> OccupancyMap:
    """A generated world's floor plan as a map (walls, pots, axis-aligned boxes): what a finished
    SLAM map of it shows, for a test of the aisles (the runtime never reads the world)."""
    w, h = int(round(world.floor.x / RES)) + 2, int(round(world.floor.y / RES)) + 2
    occ = np.zeros((h, w), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    cy, cx = (np.mgrid[0:h, 0:w] - 0.5) * RES
    for p in world.pots:
        occ[np.hypot(cx - p.x, cy - p.y) <= 0.10] = 100
    for b in world.obstacles:
        occ[(np.abs(cx - b.x) <= b.sx / 2) & (np.abs(cy - b.y) <= b.sy / 2)] = 100
    return OccupancyMap(occ, RES, -RES, -RES)


def test_a_generated_two_bay_greenhouse_has_its_row_aisles_and_its_doorways_are_open():
    from sim.generate import generate_world

    world = generate_world(3, 5, seed=2, bays=2, robots=3)
    pots = np.array([(p.x, p.y, p.facing) for p in world.pots])
    a = find_aisles(world_occupancy(world), pots)
    assert a.count == 8  # per bay: the south strip, two between rows, the north strip
    approach = pots[:, :2] + 0.5 * np.c_[np.cos(pots[:, 2]), np.sin(pots[:, 2])]
    assert (a.at(approach[:, 0], approach[:, 1]) != NO_AISLE).all()
    docks = np.array([(s.x, s.y) for s in world.spawn_poses])
    assert (a.at(docks[:, 0], docks[:, 1]) == NO_AISLE).all()  # the docks are on open ground
    divider = world.obstacles[0].x  # its doorways, 1.2 m wide at either end: two robots pass
    assert (a.at([divider] * 2, [0.6, world.floor.y - 0.6]) == NO_AISLE).all()
