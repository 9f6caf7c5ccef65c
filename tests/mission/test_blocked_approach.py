"""A pot whose approach pose something else stands on (a crate here; in a fleet, a robot that died
there) is inspected from a look beside it that reads its tag, the wrist aimed from there, and the
report says so (``mission.patrol.aside``); with no look beside it where the robot fits, it fails
saying so."""
from __future__ import annotations

import time

import pytest

from mission.jobs.patrol import run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import load_config
from sim.world import Obstacle, load_default_world

pytestmark = pytest.mark.slow


def patrol_of_p07(tmp_path, crate: Obstacle) -> tuple[dict, object]:
    """P07 alone (the middle aisle of the default greenhouse, its plate facing north), with
    ``crate`` standing on the floor."""
    world = load_default_world()
    world = world.model_copy(update={"obstacles": [crate]})
    mission = mission_from_world(world)
    mission = mission.model_copy(update={"pots": [p for p in mission.pots if p.id == "P07"]})
    doc = run_to_end(start_sim_patrol(world, mission, load_config(), tmp_path / "r.json", time.perf_counter))
    return doc, next(p for p in world.pots if p.id == "P07")


def test_a_crate_on_a_pots_approach_pose_has_it_inspected_right_from_beside_it(tmp_path):
    doc, truth = patrol_of_p07(tmp_path, Obstacle(x=4.0, y=2.5, sx=0.3, sy=0.3))  # P07 (4, 2) faces north: 0.5 m out
    (pot,) = doc["pots"]
    assert pot["status"] == "inspected" and pot["tag_read"] == truth.tag
    assert pot["flower"]["color"] == truth.flower and pot["flower"]["bug"] == truth.bug
    assert pot["wrist_view"] == "aim"  # the IK look from off the ideal pose, not the preset
    assert pot["truth_error"]["xy"] > 0.3  # it did not stand where the crate stands
    kinds = [a["kind"] for a in doc["anomalies"] if a["pot"] == "P07"]
    assert "approach_blocked" in kinds and "retried_later" not in kinds and "unreachable" not in kinds
    assert doc["outcome"] == "completed"


def test_a_pot_with_no_room_beside_its_taken_approach_pose_fails_saying_so(tmp_path):
    bench = Obstacle(x=4.0, y=2.55, sx=1.7, sy=0.3)  # along the aisle over every look within reach of P07
    doc, _ = patrol_of_p07(tmp_path, bench)
    (pot,) = doc["pots"]
    assert pot["status"] == "failed"
    (a,) = [a for a in doc["anomalies"] if a["pot"] == "P07"]
    assert a["kind"] == "unreachable" and "its approach pose is taken" in a["detail"]
    assert "did not read its tag" in a["detail"]
