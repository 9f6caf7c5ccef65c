"""A short sim patrol recorded to MCAP and read back with the ``mcap`` library: every channel,
as many messages as its rate over the run's robot time, what Foxglove expects in each; and the
recording does not change the run."""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from mission.jobs.patrol import PatrolRun, run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import Mission, mission_from_world
from mission.record.channels import GRID_BEAT, PLAN_BEAT, RATE, STATE_BEAT, STATUS_COLOURS
from mission.record.mcap_file import record_patrol
from mission.runtime.config import load_config
from sim.world import load_default_world
from tests.record.fixtures import Recording, read_mcap, seconds
from tests.record.test_channels import EXPECTED_SCHEMAS

SEED = 3


def two_pots() -> Mission:
    m = mission_from_world(load_default_world())
    return m.model_copy(update={"pots": [p for p in m.pots if p.id in ("P01", "P02")]})


def patrol(directory: Path, record: bool) -> tuple[dict, PatrolRun, float]:
    """The patrol to its end; returns the report, the run and the runtime time recording began."""
    config = load_config(env={"LUPIN_SIM__SEED": str(SEED)})
    run = start_sim_patrol(load_default_world(), two_pots(), config, directory / "report.json", time.perf_counter)
    began = run.robot.scheduler.clock.now()
    if record:
        record_patrol(run, directory / "run.mcap")
    return run_to_end(run), run, began


@dataclass
class Recorded:
    doc: dict
    run: PatrolRun
    began: float
    path: Path
    rec: Recording

    @property
    def duration(self) -> float:
        """Robot seconds recorded: from the start to the close after the report's last write."""
        return self.run.report.t0 + self.doc["sim_time_s"] - self.began


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> Recorded:
    directory = tmp_path_factory.mktemp("recorded")
    doc, run, began = patrol(directory, record=True)
    assert doc["outcome"] == "completed", doc
    return Recorded(doc, run, began, directory / "run.mcap", read_mcap(directory / "run.mcap"))


@pytest.mark.slow
def test_every_channel_is_recorded_with_the_schema_foxglove_expects(recorded):
    # /people carries messages only while the tracker follows someone (none may be seen here)
    assert set(EXPECTED_SCHEMAS) - {"/people"} <= set(recorded.rec.topics) <= set(EXPECTED_SCHEMAS)
    for topic, t in recorded.rec.topics.items():
        assert (t.schema_name, t.schema_encoding, t.message_encoding) == EXPECTED_SCHEMAS[topic], topic
    assert recorded.rec.profile == ""


@pytest.mark.slow
def test_the_recording_names_its_robot(recorded):
    from mcap.reader import make_reader

    with open(recorded.path, "rb") as f:
        metadata = {m.name: m.metadata for m in make_reader(f).iter_metadata()}
    assert metadata["lupin"] == {"robot": recorded.run.robot.config.link.robot}


@pytest.mark.slow
def test_message_counts_follow_the_rates_over_the_robot_time(recorded):
    d, n = recorded.duration, recorded.rec.counts
    assert 20 < d < 60  # two pots and home: the expectations below scale with it
    # Beats are exact on the sim clock: ticks at 0.1 s steps over [began, close], plus the
    # closing flush on every channel but the scan (no new revolution at the same instant).
    # The tolerances cover only where the run's end falls between two beats.
    per_rate = {"/tf": (RATE, 1), "/scan": (RATE, 0), "/plan": (RATE / PLAN_BEAT[0], 1),
                "/path": (RATE / PLAN_BEAT[0], 1), "/costmap/global": (RATE / GRID_BEAT[0], 1),
                "/pots": (RATE / STATE_BEAT[0], 1), "/mission/state": (RATE / STATE_BEAT[0], 1)}
    for topic, (rate, flush) in per_rate.items():
        assert abs(n[topic] - (rate * d + flush)) <= 1.5, (topic, n[topic], rate * d)
    # SLAM hands its first map back after a second or two of scans: the map starts late.
    assert d - 4 <= n["/map"] <= d + 2
    # Camera frames: exactly the captures the pipelines made (the channels never capture).
    cams = recorded.run.tree.cameras
    assert n["/camera/front/compressed"] == cams["front"].captures > 0
    assert n["/camera/wrist/compressed"] == cams["wrist"].captures >= 2  # one inspection per pot at least
    # The log: each pot as it was recorded, each anomaly, the outcome.
    assert n["/mission/log"] == len(recorded.doc["pots"]) + len(recorded.doc["anomalies"]) + 1


@pytest.mark.slow
def test_every_message_is_stamped_with_sim_time(recorded):
    start, end = round(recorded.began * 1e9), round((recorded.began + recorded.duration) * 1e9)
    for topic, t in recorded.rec.topics.items():
        assert start <= min(t.log_times) and max(t.log_times) <= end, topic
        assert t.log_times == sorted(t.log_times), topic
    tf = recorded.rec.decoded("/tf")
    assert [seconds(m["transforms"][0]["timestamp"]) * 1e9 for m in tf] == pytest.approx(
        recorded.rec.topics["/tf"].log_times, abs=1)


@pytest.mark.slow
def test_what_foxglove_draws(recorded):
    rec, run = recorded.rec, recorded.run
    last_tf = {x["child_frame_id"]: x for x in rec.decoded("/tf")[-1]["transforms"]}
    assert {k: v["parent_frame_id"] for k, v in last_tf.items()} == {
        "odom": "map", "base_link": "odom", "lidar": "base_link", "front_camera_optical": "base_link",
        "wrist_camera_optical": "base_link"}
    odom = run.robot.base.odometry.pose
    assert last_tf["base_link"]["translation"].get("x", 0.0) == pytest.approx(odom.x, abs=1e-9)

    scans = rec.decoded("/scan")
    assert {s["frame_id"] for s in scans} == {"lidar"}
    assert {len(s["ranges"]) for s in scans} == {run.robot.config.sim.lidar.points}

    grid, cm = rec.decoded("/costmap/global")[-1], run.nav.global_costmap.grid
    assert (grid["column_count"], len(grid["data"])) == (cm.width, cm.width * cm.height)
    assert grid["data"] == cm.data.tobytes()  # the final flush: the costmap as it ended
    slam = run.nav.localisation.occupancy
    assert rec.decoded("/map")[-1]["column_count"] == slam.width

    plans = rec.decoded("/plan")
    assert all(p["frame_id"] == "map" for p in plans) and max(len(p.get("poses", [])) for p in plans) > 5
    path = rec.decoded("/path")[-1]["poses"]
    driven = sum(math.dist((a["position"].get("x", 0.0), a["position"].get("y", 0.0)),
                           (b["position"].get("x", 0.0), b["position"].get("y", 0.0))) for a, b in zip(path, path[1:]))
    assert driven == pytest.approx(recorded.doc["distance_m"], rel=0.25)  # map-frame trail vs odometry

    for camera in ("front", "wrist"):
        images = rec.decoded(f"/camera/{camera}/compressed")
        assert {(i["format"], i["frame_id"]) for i in images} == {("jpeg", f"{camera}_camera_optical")}
        assert all(i["data"][:2] == b"\xff\xd8" for i in images)
    saved = (run.report.directory / "P02_wrist.jpg").read_bytes()  # the pot's own frame, as the report keeps it
    assert saved in [i["data"] for i in rec.decoded("/camera/wrist/compressed")]

    entities = rec.decoded("/pots")[-1]["entities"]
    assert [e["id"] for e in entities] == ["P01", "P02"]
    green = dict(zip("rgba", STATUS_COLOURS["inspected"]))
    assert all(e["cylinders"][0]["color"] == pytest.approx(green) for e in entities)
    assert entities[0]["texts"][0]["text"] == "P01 inspected red"

    state = rec.decoded("/mission/state")
    assert state[0]["pots_done"] == 0 and state[0]["outcome"] is None
    assert state[-1]["outcome"] == "completed" and state[-1]["pots_done"] == 2 == state[-1]["pots_total"]
    assert state[-1]["pots"] == {"P01": "inspected", "P02": "inspected"}
    assert state[-1]["tree"] == run.tree.render()
    assert {s["step"] for s in state} >= {"approach P01", "approach P02"}

    log = [m["message"] for m in rec.decoded("/mission/log")]
    assert log[0].startswith("P01 inspected") and log[-1] == "outcome completed"


@pytest.mark.slow
def test_the_recording_is_small_and_does_not_change_the_run(recorded, tmp_path):
    size = recorded.path.stat().st_size
    assert size < 0.2e6 * recorded.duration, size  # ~40 kB per robot second measured: zstd on grids
    plain, _, _ = patrol(tmp_path, record=False)
    assert not (tmp_path / "run.mcap").exists()
    strip = lambda doc: json.dumps({k: v for k, v in doc.items() if k != "wall_time_s"}, sort_keys=True)  # noqa: E731
    assert strip(plain) == strip(recorded.doc)
