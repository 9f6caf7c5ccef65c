"""One mission to a patrol per robot (fleet/assign.py) on the tiny greenhouse's costmap."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fleet.assign import assign, in_dock_frame
from mission.patrol.mission_file import Mission, MissionPot
from nav.occupancy import OccupancyMap
from tests.nav.builders import RES, greenhouse_grid, greenhouse_occupancy

ROWS, POTS_X = (1.0, 2.0, 3.0), (2.0, 3.0, 4.0, 5.0)


def tiny_mission() -> Mission:
    pots = [MissionPot(id=f"P{k + 1:02d}", x=x, y=y, facing=math.pi / 2 if y == 2.0 else -math.pi / 2)
            for k, (y, x) in enumerate((y, x) for y in ROWS for x in POTS_X)]
    return Mission(name="tiny", pots=pots, order="shortest")


def test_in_dock_frame_moves_a_pot_into_the_robots_own_map():
    pot = MissionPot(id="P", x=5.0, y=3.0, facing=-math.pi / 2)
    seen = in_dock_frame(pot, (6.0, 3.5, math.pi))
    assert (seen.x, seen.y) == pytest.approx((1.0, 0.5)) and seen.facing == pytest.approx(math.pi / 2)
    assert in_dock_frame(pot, (0.0, 0.0, 0.0)) == pot


def test_two_docks_get_their_own_balanced_missions_in_their_own_frames_ending_at_their_docks():
    m = tiny_mission()
    docks = {"r1": (1.0, 0.5, 0.0), "r2": (6.0, 3.5, math.pi)}
    a = assign(m, greenhouse_grid(), docks, occupancy=OccupancyMap(greenhouse_occupancy(), RES, 0.0, 0.0))
    assert set(a.missions) == {"r1", "r2"}
    ids = {r: [p.id for p in mm.pots] for r, mm in a.missions.items()}
    assert sorted(ids["r1"] + ids["r2"]) == [p.id for p in m.pots]
    assert all(mm.order == "as_listed" and (mm.home.x, mm.home.y) == (0.0, 0.0) and mm.name == "tiny"
               for mm in a.missions.values())
    by_id = {p.id: k for k, p in enumerate(m.pots)}
    assert {"P01", "P02", "P03", "P04"} <= set(ids["r1"])  # the south aisle, whole, to the robot docked at its end
    assert a.aisles[by_id["P01"]] != a.aisles[by_id["P12"]]
    # the middle aisle's 8 pots stay whole: shared, the two robots would take turns at its lock
    assert set(a.aisles[[by_id[i] for i in ids["r1"]]]).isdisjoint(a.aisles[[by_id[i] for i in ids["r2"]]])
    # r2's pots back in the fleet frame are the mission's
    r2 = a.missions["r2"].pots[0]
    fleet = m.pots[by_id[r2.id]]
    assert (6.0 - r2.x, 3.5 - r2.y) == pytest.approx((fleet.x, fleet.y))
    # r2 down: r1 takes all, r2 gets no mission
    alone = assign(m, greenhouse_grid(), docks, up=["r1"])
    assert list(alone.missions) == ["r1"] and len(alone.missions["r1"].pots) == 12
    assert (alone.aisles == -1).all()  # no map: no aisles
    assert np.isclose(alone.split.makespan, alone.split.lengths["r1"] + 12 * alone.split.per_pot)
