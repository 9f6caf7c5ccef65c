"""The patrol report: anomaly rules, discovered tags, atomic writes (no sim: synthetic visits)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from behaviours.visit import PotVisit
from hw.odometry import Pose2D
from mission.patrol.climate import NoClimate, TableClimate
from mission.patrol.config import PatrolConfig
from mission.patrol.mission_file import parse_mission
from mission.patrol.report import PatrolReport, not_inspected
from perception.camera_pipeline import Frame
from perception.detections import Bloom, FlowerFrame, TagRead
from sim.world import load_default_world

MISSION = {"name": "unit", "home": {"x": 0.0, "y": 0.0, "yaw": 0.0},
           "pots": [{"id": "P01", "x": 1.0, "y": 0.5, "facing": -1.5708, "tag": 1},
                    {"id": "P02", "x": 2.0, "y": 0.5, "facing": -1.5708, "tag": 2},
                    {"id": "P03", "x": 3.0, "y": 0.5, "facing": -1.5708}]}


def tag(id_, distance, right=0.0):
    """A tag read ``distance`` ahead of the front camera, facing it head-on."""
    return TagRead(id_, (), (right, 0.0, distance), (math.pi, 0.0, 0.0), 0.0, 0.1)


def frame(value=100):
    return Frame(0.0, np.full((48, 64, 3), value, np.uint8), "cam")


def bloom(cls="red", bug=False):
    return Bloom(cls, (32.0, 24.0), 900, 0.9, bug)


@pytest.fixture
def report(tmp_path):
    mission = parse_mission(MISSION, "unit.yaml")
    clock = {"t": 10.0}
    r = PatrolReport(tmp_path / "report.json", mission, PatrolConfig(), TableClimate(load_default_world().climate_readings()),
                     lambda: clock["t"], lambda: 0.0, lambda: 3.5, lambda goal: {"xy": 0.01, "yaw": 0.0})
    return r, mission


def visited(arrived=Pose2D(1.0, 0.0, 1.5708), blooms=(bloom(),), tags=(tag(1, 0.27),)):
    v = PotVisit("P01", attempts=1, arrived=arrived)
    v.wrist, v.flower = frame(), FlowerFrame(tuple(blooms))
    v.front, v.tags = frame(), tuple(tags)
    return v


def kinds(r, pot):
    return [a["kind"] for a in r.anomalies if a["pot"] == pot]


def test_a_clean_pot_has_no_anomaly_and_its_climate(report):
    r, m = report
    r.record(m.pots[0], visited(), Pose2D(1.0, 0.0, 1.5708))
    entry = r.pots["P01"]
    assert kinds(r, "P01") == []
    assert entry["status"] == "inspected" and entry["tag_read"] == 1
    assert entry["flower"] == {"color": "red", "blooms": 1, "bug": False, "confidence": 0.9}
    assert entry["climate"]["temperature"] == 22.5 and entry["approach_error"] == {"xy": 0.0, "yaw": 0.0}


def test_each_anomaly_rule(report):
    r, m = report
    r.record(m.pots[0], visited(blooms=(bloom("pink", bug=True),), tags=(tag(2, 0.27),)), Pose2D(1.0, 0.0, 1.5708))
    assert kinds(r, "P01") == ["bug", "tag_mismatch"]
    v = visited(blooms=(), tags=(tag(2, 0.95),))  # the next pot's tag, too far to be this one's
    v.id = "P02"
    r.record(m.pots[1], v, Pose2D(2.0, 0.0, 1.5708))
    assert kinds(r, "P02") == ["no_bloom", "no_tag"]
    assert r.pots["P02"]["tag_read"] is None


def test_climate_is_keyed_by_the_tag_read_only(report):
    """A pot whose tag was not read gets no climate, not its expected tag's; a swapped pot gets
    the climate of the tag it carries."""
    r, m = report
    r.record(m.pots[0], visited(tags=()), Pose2D(1.0, 0.0, 1.5708))
    assert r.pots["P01"]["tag_read"] is None and "climate" not in r.pots["P01"]
    r.record(m.pots[0], visited(tags=(tag(4, 0.27),)), Pose2D(1.0, 0.0, 1.5708))  # P01 expects tag 1
    assert r.pots["P01"]["climate"]["temperature"] == 23.1  # tag 4's, not tag 1's 22.5


def test_arm_unavailable_still_reads_the_tag(report):
    r, m = report
    v = visited()
    v.wrist, v.flower = None, None
    v.failures["arm"] = "arm unavailable: shoulder_lift latched"
    r.record(m.pots[0], v, Pose2D(1.0, 0.0, 1.5708))
    assert kinds(r, "P01") == ["arm_unavailable"]
    assert r.pots["P01"]["flower"] is None and r.pots["P01"]["tag_read"] == 1
    assert r.pots["P01"]["images"] == ["P01_front.jpg"]


def test_every_pot_not_inspected_is_counted_by_why(report):
    r, m = report
    r.record(m.pots[0], visited(blooms=()), Pose2D(1.0, 0.0, 1.5708))  # inspected, with a no_bloom anomaly
    v = PotVisit("P02", attempts=2)
    v.failures["approach"] = "navigation failed: no path"
    r.record(m.pots[1], v, Pose2D(2.0, 0.0, 1.5708))
    assert not_inspected(r.finish("battery_low")) == {"unreachable": 1, "skipped": 1}


def test_an_unreachable_pot(report):
    r, m = report
    v = PotVisit("P02", attempts=2)
    v.failures["approach"] = "navigation failed: no path"
    r.record(m.pots[1], v, Pose2D(2.0, 0.0, 1.5708))
    entry = r.pots["P02"]
    assert entry["status"] == "failed" and entry["attempts"] == 2 and "truth_error" not in entry
    assert r.anomalies == [{"kind": "unreachable", "pot": "P02", "detail": "2 attempt(s): navigation failed: no path"}]


def test_the_report_on_disk_is_always_whole_and_the_end_marks_skipped_pots(report, tmp_path):
    r, m = report
    r.record(m.pots[0], visited(), Pose2D(1.0, 0.0, 1.5708))
    doc = json.loads((tmp_path / "report.json").read_text())
    assert doc["outcome"] is None and [p["id"] for p in doc["pots"]] == ["P01"]
    assert (tmp_path / "P01_wrist.jpg").stat().st_size > 0
    final = r.finish("aborted")
    assert [p["status"] for p in final["pots"]] == ["inspected", "skipped", "skipped"]
    assert [(a["kind"], a["pot"]) for a in final["anomalies"]] == [("skipped", "P02"), ("skipped", "P03")]
    assert final["anomalies"][0]["detail"] == "not visited: the patrol ended aborted"
    assert json.loads((tmp_path / "report.json").read_text()) == final
    assert final["distance_m"] == 3.5 and final["sim_time_s"] == 0.0
    assert not list(tmp_path.glob(".*.tmp"))


def test_discovered_tags_are_unlisted_near_enough_and_fused_with_the_pot_they_place(report):
    r, _ = report
    robot = Pose2D(0.0, 0.0, 0.0)
    r.saw((tag(1, 0.5), tag(9, 0.5), tag(9, 2.0, right=0.3)), robot)  # 1 is listed; the far 9 is too far
    r.saw((tag(9, 0.6),), robot)
    (d,) = r.document()["discovered_tags"]
    assert (d["id"], d["sightings"]) == (9, 2)
    assert 0.1625 + 0.5 < d["x"] < 0.1625 + 0.55 and d["y"] == pytest.approx(0.0, abs=1e-9)  # the near read weighs most
    assert d["pot"]["x"] == pytest.approx(d["x"] + 0.104, abs=1e-3) and abs(d["pot"]["facing"]) == pytest.approx(math.pi, abs=1e-3)


def test_no_climate_source_means_no_climate_key(tmp_path):
    mission = parse_mission(MISSION, "unit.yaml")
    r = PatrolReport(tmp_path / "r.json", mission, PatrolConfig(), NoClimate(), lambda: 0.0, lambda: 0.0, lambda: 0.0)
    r.record(mission.pots[0], visited(), Pose2D(1.0, 0.0, 1.5708))
    assert "climate" not in r.pots["P01"] and "truth_error" not in r.pots["P01"]
