"""The moved test looks past the map's drift: unmoved pots along a row whose map has drifted
several centimetres are not moved; a pot moved among them still is."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from behaviours.visit import PotVisit
from hw.odometry import Pose2D
from mission.patrol.config import PatrolConfig
from mission.patrol.map_drift import MapDrift, corrections, in_mission_frame, walls_apart
from mission.patrol.mission_file import Mission, MissionPot
from mission.patrol.pot_finder import PotFinder
from nav.localisation import OdometryOnly
from nav.occupancy import OccupancyMap
from nav.slam.checkpoint import Checkpoint
from tests.mission.test_tag_sightings import read

CONFIG = PatrolConfig()
ROW = [MissionPot(id=f"P{i:02d}", x=float(i), y=0.0, facing=math.pi / 2, tag=i) for i in range(20)]
MISSION = Mission(name="row", pots=ROW)


def drift_at(x: float) -> tuple[float, float]:
    """SLAM's map off the mission's frame: 4.5 mm per metre along the row, 3.5 across it."""
    return 0.0045 * x, -0.0035 * x


def visit(finder: PotFinder, pot: MissionPot, moved: tuple[float, float] = (0.0, 0.0)) -> PotVisit:
    """The robot at its approach pose believes it is ``drift`` off; the pot is ``moved`` off."""
    true = Pose2D(*MISSION.approach(pot))
    dx, dy = drift_at(pot.x)
    believed = Pose2D(true.x + dx, true.y + dy, true.yaw)
    ahead = MISSION.standoff - CONFIG.plate_offset - CONFIG.front_camera_mount[0]
    tag = read(pot.tag, -moved[0], ahead - moved[1])  # robot faces -y: right is -x, ahead is -y
    v = PotVisit(pot.id)
    assert finder.place(pot, v, (tag,), believed, CONFIG.tag_max_distance)
    return v


def test_unmoved_pots_on_a_drifting_map_are_not_moved_and_one_moved_among_them_is():
    finder = PotFinder(MISSION, None, CONFIG)
    moved_at = {14: (0.0, -0.07)}  # 7 cm towards the aisle, where the drift is already 7 cm
    verdicts = {pot.id: visit(finder, pot, moved_at.get(i, (0.0, 0.0))).moved for i, pot in enumerate(ROW)}
    assert math.hypot(*drift_at(19)) > 2 * CONFIG.moved_xy  # the drift alone would trip the test
    assert [p for p, m in verdicts.items() if m] == ["P14"]


def test_without_the_drift_estimate_the_same_row_reports_unmoved_pots_as_moved():
    finder = PotFinder(MISSION, None, CONFIG)
    finder.drift = MapDrift(radius=1e-9, agree=CONFIG.moved_xy / 2)  # no neighbours ever
    verdicts = [visit(finder, pot).moved for pot in ROW]
    assert sum(verdicts) >= 5


def test_the_drift_is_what_most_neighbours_agree_on_and_nothing_when_they_do_not():
    drift = MapDrift(radius=3.0, agree=0.025)
    drift.record((0.0, 0.0), (0.04, 0.0))
    drift.record((1.0, 0.0), (0.041, 0.002))
    assert drift.near(2.0, 0.0) == pytest.approx((0.0405, 0.001))
    assert drift.near(9.0, 0.0) == (0.0, 0.0)  # none near
    drift.record((2.0, 0.0), (0.04, 0.001))
    drift.record((3.0, 0.0), (-0.15, 0.1))  # a moved pot among the three read last is outvoted
    assert drift.near(2.2, 0.0) == pytest.approx(((0.041 + 0.04) / 2, 0.0015))
    drift.record((2.5, 0.0), (0.2, -0.1))
    drift.record((1.5, 0.0), (-0.1, -0.2))  # as many moved as not: no consensus
    assert drift.near(2.2, 0.0) == (0.0, 0.0)


def test_a_pot_off_by_the_drift_alone_is_approached_where_the_drift_puts_it():
    finder = PotFinder(MISSION, None, CONFIG)
    for pot in ROW[:-1]:
        visit(finder, pot)
    last = ROW[-1]
    goal = finder.approach(last, PotVisit(last.id))  # before its own tag is read
    dx, dy = drift_at(last.x)
    ideal = MISSION.approach(last)
    assert math.hypot(goal.x - ideal[0] - dx, goal.y - ideal[1] - dy) < 0.02  # within 2 cm (the neighbours lag a growing drift)
    assert math.hypot(dx, dy) > 0.08  # the mission's pose alone would be 8 cm off
    assert not visit(finder, last).moved


def test_a_moved_pot_is_placed_in_the_missions_frame_and_not_moved_again_after_the_update():
    """The report's (and ``mission update``'s) pose of a moved pot is the drift-corrected one the
    decision used: written back, the next patrol on a map that drifts alike finds it in place."""
    finder = PotFinder(MISSION, None, CONFIG)
    moved_at = {14: (0.0, -0.07)}
    visits = {pot.id: visit(finder, pot, moved_at.get(i, (0.0, 0.0))) for i, pot in enumerate(ROW)}
    p14, v = ROW[14], visits["P14"]
    x, y, _ = in_mission_frame(v)
    assert v.moved and math.hypot(*v.drift) > 0.05
    assert math.hypot(x - p14.x, y - (p14.y - 0.07)) < 0.015  # where it stands, not where the drifted map saw it
    assert math.hypot(v.located[0] - p14.x, v.located[1] - (p14.y - 0.07)) > 0.05  # the raw read is the drift off
    updated = p14.model_copy(update={"x": x, "y": y})
    second = PotFinder(Mission(name="row", pots=[*ROW[:14], updated, *ROW[15:]]), None, CONFIG)
    for pot in ROW[:14]:
        visit(second, pot)
    true = Pose2D(*MISSION.approach(p14))
    dx, dy = drift_at(p14.x)
    believed = Pose2D(true.x + dx, true.y + dy, true.yaw)
    ahead = MISSION.standoff - CONFIG.plate_offset - CONFIG.front_camera_mount[0]
    again = PotVisit(p14.id)
    assert second.place(updated, again, (read(p14.tag, 0.0, ahead + 0.07),), believed, CONFIG.tag_max_distance)
    assert not again.moved


def test_the_first_pots_judged_without_a_drift_are_judged_again_at_the_end():
    """A map 7 cm off everywhere: the first two pots have no neighbours to read the drift off
    and are provisionally moved; at the end, with the row located, they are not."""
    finder = PotFinder(MISSION, None, CONFIG)
    ahead = MISSION.standoff - CONFIG.plate_offset - CONFIG.front_camera_mount[0]
    visits = {}
    for pot in ROW[:8]:
        true = Pose2D(*MISSION.approach(pot))
        v = visits[pot.id] = PotVisit(pot.id)
        assert finder.place(pot, v, (read(pot.tag, 0.0, ahead),), Pose2D(true.x + 0.07, true.y, true.yaw),
                            CONFIG.tag_max_distance)
    first = [p.id for p in ROW[:8] if visits[p.id].moved]
    assert first == ["P00", "P01"] and not visits["P00"].drift_known
    changed = finder.rejudge(visits)
    assert [p.id for p in changed] == ["P00", "P01"]
    assert not any(v.moved for v in visits.values())
    assert visits["P00"].drift == pytest.approx((0.07, 0.0), abs=0.01)


def test_neighbours_beyond_a_wall_do_not_give_the_drift():
    """A divider between x = 2 and x = 3: pots past it are judged on their own side only."""
    grid = np.zeros((40, 200), dtype=np.int8)
    occupancy = OccupancyMap(grid, 0.05, -1.0, -1.0)
    occupancy.occupancy[:, int((2.5 + 1.0) / 0.05)] = 100  # the wall at x = 2.5
    apart = walls_apart(occupancy)
    assert apart((2.0, 0.0), (3.0, 0.0)) and not apart((3.0, 0.0), (4.0, 0.0))
    drift = MapDrift(radius=3.0, agree=0.025)
    drift.apart = apart
    drift.record((1.0, 0.0), (0.10, 0.0))
    drift.record((2.0, 0.0), (0.10, 0.0))
    assert drift.consensus(3.0, 0.0) is None  # only the other bay's pots are near
    drift.record((4.0, 0.0), (0.02, 0.0))
    drift.record((5.0, 0.0), (0.02, 0.0))
    assert drift.consensus(3.0, 0.0).offset == pytest.approx((0.02, 0.0))


def test_the_end_never_adds_a_moved_verdict():
    """The first pot read in place, its neighbours an hour later with the drift grown 8 cm: the
    end's judgement takes back only provisional moved verdicts, it does not make new ones."""
    finder = PotFinder(MISSION, None, CONFIG)
    ahead = MISSION.standoff - CONFIG.plate_offset - CONFIG.front_camera_mount[0]
    visits = {}
    for pot, off in zip(ROW[:5], (0.0, 0.08, 0.08, 0.08, 0.08)):
        true = Pose2D(*MISSION.approach(pot))
        v = visits[pot.id] = PotVisit(pot.id)
        finder.place(pot, v, (read(pot.tag, 0.0, ahead),), Pose2D(true.x + off, true.y, true.yaw), CONFIG.tag_max_distance)
    assert not visits["P00"].moved and not visits["P00"].drift_known
    changed = [p.id for p in finder.rejudge(visits)]
    assert changed == ["P01", "P02"]  # provisionally moved by the 8 cm with no neighbours yet: taken back
    assert not visits["P00"].moved  # its neighbours' later drift does not make it moved


TWO_ROWS = [MissionPot(id=f"{r}{i}", x=float(i), y=float(k), facing=math.pi / 2, tag=10 * k + i + 1)
            for k, r in enumerate("AB") for i in range(10)]


def read_off(finder: PotFinder, pot: MissionPot, off: tuple[float, float], moved: tuple[float, float] = (0.0, 0.0)) -> PotVisit:
    """``pot`` read with the robot believing itself ``off`` from where it stands, the pot
    ``moved`` off the mission's position."""
    true = Pose2D(*Mission(name="rows", pots=TWO_ROWS).approach(pot))
    ahead = MISSION.standoff - CONFIG.plate_offset - CONFIG.front_camera_mount[0]
    v = PotVisit(pot.id)
    assert finder.place(pot, v, (read(pot.tag, -moved[0], ahead - moved[1]),),
                        Pose2D(true.x + off[0], true.y + off[1], true.yaw), CONFIG.tag_max_distance)
    return v


def test_the_drift_is_read_off_the_neighbours_read_lately_not_a_row_read_long_before():
    """Row A read with the map 15 cm off; row B beside it read later, the error grown along it to
    24 cm (the 180-pot patrol in listed order, its last rows): row A's older reads, outvoting row
    B's, made B's far pots moved; the pots read just before each say its drift. One pot of B
    moved 7 cm still is moved."""
    finder = PotFinder(Mission(name="rows", pots=TWO_ROWS), None, CONFIG)
    rows = {p.id: p for p in TWO_ROWS}
    assert [i for i in range(10) if read_off(finder, rows[f"A{i}"], (0.0, -0.15)).moved] == [0, 1]  # the patrol's first
    verdicts = {f"B{i}": read_off(finder, rows[f"B{i}"], (0.0, -0.15 - 0.01 * i), (0.07, 0.0) if i == 5 else (0.0, 0.0)).moved
                for i in range(10)}
    assert [p for p, m in verdicts.items() if m] == ["B5"]


def test_a_solve_starts_the_drift_afresh_and_the_pots_read_just_after_are_judged_again():
    """Row A read with the robot 6 cm off (its error grown since SLAM last solved its pose
    graph); a loop closure's solve pulls it back onto the map; row B beside it read right. The
    pots read just after the solve have only row A's reads near them: provisionally moved, and
    at the end, judged on B's reads since the solve, not moved. The solves are SLAM's count."""
    checkpoint = Checkpoint()
    checkpoint.counters = (900, 12, 3, 40.0)  # scans, loop closures, solves, next loop
    assert corrections(SimpleNamespace(checkpoint=checkpoint)) == 3
    assert corrections(None) == corrections(OdometryOnly()) == 0
    finder = PotFinder(Mission(name="rows", pots=TWO_ROWS), None, CONFIG)
    closures = [0]
    finder.drift.epoch = lambda: closures[0]
    rows = {p.id: p for p in TWO_ROWS}
    visits = {}
    for i in range(10):
        visits[f"A{i}"] = read_off(finder, rows[f"A{i}"], (0.0, 0.06))
    closures[0] = 1
    for i in range(10):
        visits[f"B{i}"] = read_off(finder, rows[f"B{i}"], (0.0, 0.0))
    early = [p for p, v in visits.items() if v.moved]
    assert early == ["A0", "A1", "B0", "B1"] and not any(visits[p].drift_known for p in early)  # A0, A1: the patrol's first
    assert [p.id for p in finder.rejudge(visits)] == early
    assert not any(v.moved for v in visits.values())
