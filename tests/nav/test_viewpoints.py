"""Pots found in the map as small things standing apart, the lattice they stand on, and the
looks at them from every side the robot fits."""
from __future__ import annotations

import math

import numpy as np
import pytest

from nav.costmap.grid import CostGrid, FREE, INSCRIBED, LETHAL
from nav.costmap.inflation import InflationLayer
from nav.occupancy import OccupancyMap
from nav.viewpoints import Look, lanes, lattice_angle, looks, pot_blobs

POT_RADIUS = 0.10
"""The pots drawn below (the sim's, spec/world.md)."""


def greenhouse(angle: float = 0.0) -> tuple[OccupancyMap, list[tuple[float, float]]]:
    """A 6 x 5 m map, walls round it, 3 x 2 pots 1 m apart on a lattice turned by ``angle``;
    each pot seen as the arc of its side facing south-west (as the lidar would from the dock), its
    inside and the shadow behind it unknown."""
    occ = np.zeros((100, 120), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    c, s = math.cos(angle), math.sin(angle)
    centres = [(2.0 + c * i - s * j, 1.8 + s * i + c * j) for i in range(3) for j in range(2)]
    ys, xs = (np.mgrid[0:100, 0:120] + 0.5) * 0.05
    for px, py in centres:
        behind = ((xs - px) + (ys - py) > -0.05) & (np.hypot(xs - px, ys - py) < 0.3)
        occ[(np.hypot(xs - px, ys - py) < 0.1) | behind] = -1
    for px, py in centres:
        for t in np.linspace(math.pi, 1.5 * math.pi, 12):
            occ[int((py + 0.1 * math.sin(t)) / 0.05), int((px + 0.1 * math.cos(t)) / 0.05)] = 100
    return OccupancyMap(occ, 0.05, 0.0, 0.0), centres


def costmap_of(m: OccupancyMap) -> CostGrid:
    raw = np.where(m.occupancy >= 65, LETHAL, FREE).astype(np.uint8)
    return CostGrid(InflationLayer(0.05, 0.22, 0.25, 5.0).apply(raw), 0.05, 0.0, 0.0)


def test_pots_are_the_small_clusters_and_the_walls_are_not():
    m, centres = greenhouse()
    blobs = pot_blobs(m, POT_RADIUS)
    assert len(blobs) == 6
    for px, py in centres:  # the arc is one side, its centre of mass 6 cm off; the fit half a cell
        assert np.hypot(blobs[:, 0] - px, blobs[:, 1] - py).min() < 0.03


def test_a_pot_seen_from_one_side_is_centred_behind_its_arc_not_in_front():
    """A quarter arc fits a circle on either side equally well; the one with seen-through
    (free) cells inside is the mirror image on the lidar's side."""
    m, centres = greenhouse()
    arc_only = OccupancyMap(np.where(m.occupancy == 100, 100, -1).astype(np.int8), 0.05, 0.0, 0.0)
    ambiguous = pot_blobs(arc_only, POT_RADIUS)
    fitted = pot_blobs(m, POT_RADIUS)
    d = lambda b: np.array([np.hypot(b[:, 0] - px, b[:, 1] - py).min() for px, py in centres])
    assert d(fitted).max() < 0.03
    assert d(ambiguous).max() > d(fitted).max()  # with nothing seen through, no side wins


@pytest.mark.parametrize("angle", [0.0, 0.3, -0.2])
def test_the_lattice_angle_is_the_rows_direction_folded_to_a_right_angle(angle):
    m, _ = greenhouse(angle)
    assert lattice_angle(pot_blobs(m, POT_RADIUS)) == pytest.approx(angle, abs=0.05)


def test_looks_face_their_pot_from_each_side_the_robot_fits():
    m, _ = greenhouse()
    blobs = pot_blobs(m, POT_RADIUS)
    cm = costmap_of(m)
    views = looks(blobs, cm, 0.5)
    assert all(int(cm.cost_at(v.x, v.y)) < INSCRIBED for v in views)
    for v in views:  # half a metre out, facing the pot
        px, py = blobs[v.pot]
        assert math.hypot(px - v.x, py - v.y) == pytest.approx(0.5)
        assert math.atan2(py - v.y, px - v.x) == pytest.approx(v.yaw, abs=1e-6)
    per_pot = np.bincount([v.pot for v in views], minlength=len(blobs))
    assert per_pot.min() >= 3 and per_pot.max() == 4  # the side by a wall is too tight for some


def test_looks_string_into_lanes_along_the_rows_cut_at_gaps():
    """Looks facing north at three pots a metre apart along y = 0.5, and two more past a 3 m
    gap: two lanes, each in order, each of one heading; a look the other way is its own lane."""
    north = [Look(x, 0.5, math.pi / 2, i) for i, x in enumerate((1.0, 2.0, 3.0, 6.0, 7.0))]
    south = [Look(2.0, 1.5, -math.pi / 2, 9)]
    out = lanes(north + south, 0.0)
    got = sorted((tuple(v.pot for v in lane.looks), round(lane.length, 3)) for lane in out)
    assert got == [((0, 1, 2), 2.0), ((3, 4), 1.0), ((9,), 0.0)]
    lane = next(lane for lane in out if len(lane.looks) == 3)
    assert lane.reversed().start == lane.end and lane.reversed().looks[0].pot == 2


def test_a_pot_pushed_into_the_aisle_is_looked_at_slanted_where_square_on_is_blocked():
    """Two rows a metre apart, their pots drawn whole; the middle pot of the south row pushed
    0.2 m into the aisle: square on from the aisle the robot would stand 0.2 m from the pot
    across (inside its inscribed radius), so no look faces it from there, but slanted looks do
    (the two-bay greenhouse's P18 was never found for want of one)."""
    occ = np.zeros((80, 120), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    pushed = (3.0, 2.0)
    centres = [(x, 1.8) for x in (2.0, 4.0)] + [pushed] + [(x, 2.8) for x in (2.0, 3.0, 4.0)]
    for px, py in centres:
        for t in np.linspace(0.0, 2 * math.pi, 40, endpoint=False):
            occ[int((py + 0.1 * math.sin(t)) / 0.05), int((px + 0.1 * math.cos(t)) / 0.05)] = 100
    m = OccupancyMap(occ, 0.05, 0.0, 0.0)
    blobs, cm = pot_blobs(m, POT_RADIUS), costmap_of(m)
    k = int(np.argmin(np.hypot(blobs[:, 0] - pushed[0], blobs[:, 1] - pushed[1])))

    def from_the_aisle(views):  # looking at the pushed pot from the north, within 45 deg
        return [v for v in views if v.pot == k and abs(math.remainder(v.yaw + math.pi / 2, 2 * math.pi)) < math.pi / 4]

    assert from_the_aisle(looks(blobs, cm, 0.5)) == []
    slanted = from_the_aisle(looks(blobs, cm, 0.5, (0.25, 0.5)))
    assert len(slanted) == 2 and all(int(cm.cost_at(v.x, v.y)) < INSCRIBED for v in slanted)
    assert {v.x > pushed[0] for v in slanted} == {True, False}  # one on either hand
    for v in slanted:  # still half a metre out, facing the pot
        assert math.hypot(blobs[k][0] - v.x, blobs[k][1] - v.y) == pytest.approx(0.5)
        assert math.atan2(blobs[k][1] - v.y, blobs[k][0] - v.x) == pytest.approx(v.yaw, abs=1e-6)
    square, both = looks(blobs, cm, 0.5), looks(blobs, cm, 0.5, (0.25, 0.5))
    assert set(square) <= set(both)  # a side square on fits is looked at square on, as before
