"""A map true to a two-bay greenhouse (issue 30, item 3): the smallest run that shows it.

A survey (every pot's approach pose, then home) of a generated greenhouse two bays wide, the
divider between them seen from both sides, with the whole stack live; the whole final map is
judged against the world file: its occupied cells within 10 cm of the walls, pots and divider,
and every metre of every long wall face (the outer walls, both faces of the divider) drawn
within 5 cm of where it stands.
"""
from __future__ import annotations

import pytest

from mission.jobs.map_quality import long_wall_faces, map_quality, wall_errors
from mission.jobs.slam_drive import survey
from mission.runtime.config import load_config
from sim.generate import generate_world

pytestmark = pytest.mark.slow


def test_a_two_bay_greenhouse_is_mapped_true_to_its_walls_within_10_cm():
    world = generate_world(4, 3, 1, bays=2)  # two 6 x 5 m bays behind a divider with doorways at its ends
    run, log = survey(world, load_config(env={}))
    try:
        occupancy = run.final_map()
        assert log.outcomes.count("succeeded") == len(log.outcomes)
        q = map_quality(occupancy, world, run.spawn, tolerance=0.10)
        assert q.recall >= 0.95 and q.precision >= 0.95, q
        assert len(long_wall_faces(world)) >= 6  # four outer faces and the divider's two
        errors = wall_errors(occupancy, world, run.spawn)
        assert len(errors) >= 20 and max(abs(e) for e in errors) <= 0.05, errors
    finally:
        run.close()
