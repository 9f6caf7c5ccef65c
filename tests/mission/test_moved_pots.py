"""Pots found where they are: a moved pot is approached again from where its tag puts it and
reported ``moved`` with the measured pose; a pot taken away is searched for, then ``not_found``."""
from __future__ import annotations

import math
import time

import pytest

from hw.odometry import Pose2D
from mission.jobs.patrol import run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import load_config
from nav.frames import compose, inverse
from sim.generate import generate_world, moved_pots

pytestmark = pytest.mark.slow


def in_map(world, pot) -> Pose2D:
    return compose(inverse(Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw)), Pose2D(pot.x, pot.y, pot.facing))


def test_a_moved_pot_is_inspected_from_where_it_is_and_reported_moved(tmp_path):
    world = generate_world(3, 5, 2)
    mission = mission_from_world(world)
    mission = mission.model_copy(update={"pots": [p for p in mission.pots if p.id in ("P01", "P03")]})
    moved = moved_pots(world, 2, 6)  # P01 among them: 0.17 m towards the wall, turned 0.04 rad
    assert (moved.pots[0].x, moved.pots[0].y) != (world.pots[0].x, world.pots[0].y) and moved.pots[2] == world.pots[2]
    doc = run_to_end(start_sim_patrol(moved, mission, load_config(), tmp_path / "r.json", time.perf_counter))
    assert [p["status"] for p in doc["pots"]] == ["inspected", "inspected"]
    assert all(p["tag_read"] == p["tag_expected"] for p in doc["pots"])
    kinds = [(a["kind"], a["pot"]) for a in doc["anomalies"] if a["kind"] in ("moved", "no_tag", "not_found")]
    assert kinds == [("moved", "P01")]  # only the moved one
    a = next(a for a in doc["anomalies"] if a["kind"] == "moved")
    truth = in_map(moved, moved.pots[0])
    assert math.hypot(a["x"] - truth.x, a["y"] - truth.y) <= 0.05
    assert abs(math.remainder(a["facing"] - truth.yaw, 2 * math.pi)) <= 0.1
    p01 = next(p for p in doc["pots"] if p["id"] == "P01")
    assert p01["truth_error"]["xy"] <= 0.1  # inspected from the approach pose of where it is


def test_a_pot_taken_away_is_searched_for_then_not_found(tmp_path):
    world = generate_world(2, 3, 4)
    mission = mission_from_world(world)
    gone = world.model_copy(update={"pots": [p for p in world.pots if p.id != "P02"]})
    mission = mission.model_copy(update={"pots": [p for p in mission.pots if p.id in ("P02", "P03")], "order": "as_listed"})
    config = load_config(env={"LUPIN_PATROL__SEARCH_TIME": "25"})  # a shorter search than a patrol's 90 s
    doc = run_to_end(start_sim_patrol(gone, mission, config, tmp_path / "r.json", time.perf_counter))
    p02 = next(p for p in doc["pots"] if p["id"] == "P02")
    assert p02["status"] == "failed" and "search" in p02["failures"]
    a = next(a for a in doc["anomalies"] if a["pot"] == "P02")
    assert a["kind"] == "not_found" and "tag 2 not found within 1 m" in a["detail"]
    assert [a["kind"] for a in doc["anomalies"] if a["pot"] == "P02"] == ["not_found"]
    assert next(p for p in doc["pots"] if p["id"] == "P03")["status"] == "inspected" and doc["outcome"] == "completed"
