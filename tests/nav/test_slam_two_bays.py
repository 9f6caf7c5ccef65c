"""A map true to a two-bay greenhouse (issue 30, item 3): the smallest run that shows it.

A survey (every pot's approach pose, then home) of a generated greenhouse two bays wide, the
divider between them seen from both sides, with the whole stack live; the whole final map is
judged against the world file: its occupied cells within 10 cm of the walls, pots and divider,
and every metre of every long wall face (the outer walls, both faces of the divider) drawn
within 5 cm of where it stands.

That world is small enough that the registration's old heading bias (the scan thinned to 1.5
voxels, kiss-icp's first return of each cell in beam order: ``nav.slam.lidar_odometry``) still
drew it within 3 cm; the bias showed on the 180-pot greenhouse, where the dock's first turn left
the heading ~4 mrad short for good and the walls 18-36 m away were drawn 7-15 cm off. A survey of
it is a benchmark (``slam.large``), so its smallest run is the drive to the first three pots: it
judges the heading through that turn against the sim's truth (-4.3 mrad with the old thinning,
+0.2 mrad now) and the map drawn so far.
"""
from __future__ import annotations

import numpy as np
import pytest

from hw.odometry import wrap_angles
from mission.approach import approach_pose
from mission.jobs.map_quality import long_wall_faces, map_quality, wall_errors
from mission.jobs.navigate import start_navigate
from mission.jobs.slam_drive import SurveyLog, record, survey
from mission.runtime.config import load_config
from sim.generate import generate_world

pytestmark = pytest.mark.slow


def _surveyed_true_within_10_cm(world) -> list[float]:
    """Survey ``world``; every goal reached and the map's precision and recall within 10 cm at
    least 0.95 (asserted); the long walls' errors, m."""
    run, log = survey(world, load_config(env={}))
    try:
        occupancy = run.final_map()
        assert log.outcomes.count("succeeded") == len(log.outcomes)
        q = map_quality(occupancy, world, run.spawn, tolerance=0.10)
        assert q.recall >= 0.95 and q.precision >= 0.95, q
        return wall_errors(occupancy, world, run.spawn)
    finally:
        run.close()


def test_a_two_bay_greenhouse_is_mapped_true_to_its_walls_within_10_cm():
    world = generate_world(4, 3, 1, bays=2)  # two 6 x 5 m bays behind a divider with doorways at its ends
    assert len(long_wall_faces(world)) >= 6  # four outer faces and the divider's two
    errors = _surveyed_true_within_10_cm(world)
    assert len(errors) >= 20 and max(abs(e) for e in errors) <= 0.05, errors


def test_a_two_bay_aisle_keeps_the_wall_it_runs_along():
    """One row a bay: a 22 m aisle beside the south wall, so most beams that reach the wall
    meet it at a grazing angle. Those beams cleared the wall cells the square-on beams had hit
    (views of it disagree by a centimetre or two) and the map kept 0.88 of its walls within
    10 cm; a grazing miss that spares cells leaning occupied keeps them (``nav.slam.grid``)."""
    errors = _surveyed_true_within_10_cm(generate_world(1, 8, 1, bays=2))
    assert len(errors) >= 40 and max(abs(e) for e in errors) <= 0.03, errors


def test_the_180_pot_greenhouses_heading_holds_through_the_docks_first_turn():
    world = generate_world(6, 15, 1, bays=2)  # patrol.large's: 1 mrad of heading is 3.6 cm at its far end
    run = start_navigate(world, load_config(env={}))
    log = SurveyLog()
    record(run, log)
    try:
        outcomes = [run.go(approach_pose(p.x, p.y, p.facing), 60.0) for p in world.pots[:3]]
        run.robot.scheduler.step()  # the reply to the last scan
        log.take_reply(run.nav.localisation.last_reply)
        assert outcomes == ["succeeded"] * 3
        a = log.arrays()
        turned = np.flatnonzero(np.abs(wrap_angles(a["truth"][:, 2] - a["truth"][0, 2])) > 1.2)
        assert len(turned) > 20  # the robot turned to face the first pot
        heading = wrap_angles(a["slam"][turned[0]:, 2] - a["truth"][turned[0]:, 2])
        assert abs(float(np.median(heading))) <= 0.0015, heading  # the old thinning: -0.0043
        occupancy = run.final_map()
        assert map_quality(occupancy, world, run.spawn, tolerance=0.10).precision >= 0.95
        errors = wall_errors(occupancy, world, run.spawn)
        assert len(errors) >= 10 and max(abs(e) for e in errors) <= 0.05, errors
    finally:
        run.close()
