"""The channels on stand-in parts: which topics, which schemas, on which beats, stamped with
the runtime clock; a failing source never reaches the control loop; nothing is built for
nobody."""
from __future__ import annotations

import logging
import math
from types import SimpleNamespace

import numpy as np
import pytest

from hw.interfaces import LidarScan
from hw.people import Person
from mission.record.channels import GRID_BEAT, PLAN_BEAT, RATE, TOPICS, PatrolChannels, pot_statuses
from mission.record.messages import matrix_quaternion, optical_rotation, uniform_scan
from mission.record.mcap_file import McapRecording
from tests.record.fixtures import fake_parts, read_mcap, seconds

#: What Foxglove expects on each topic: (schema name, schema encoding, message encoding).
EXPECTED_SCHEMAS = {
    "/tf": ("foxglove.FrameTransforms", "protobuf", "protobuf"),
    "/scan": ("foxglove.LaserScan", "protobuf", "protobuf"),
    "/plan": ("foxglove.PosesInFrame", "protobuf", "protobuf"),
    "/path": ("foxglove.PosesInFrame", "protobuf", "protobuf"),
    "/costmap/global": ("foxglove.Grid", "protobuf", "protobuf"),
    "/map": ("foxglove.Grid", "protobuf", "protobuf"),
    "/pots": ("foxglove.SceneUpdate", "protobuf", "protobuf"),
    "/people": ("foxglove.SceneUpdate", "protobuf", "protobuf"),
    "/camera/front/compressed": ("foxglove.CompressedImage", "protobuf", "protobuf"),
    "/camera/wrist/compressed": ("foxglove.CompressedImage", "protobuf", "protobuf"),
    "/mission/state": ("lupin.MissionState", "jsonschema", "json"),
    "/mission/log": ("foxglove.Log", "protobuf", "protobuf"),
}


def beats(ticks: int, every: int, phase: int) -> int:
    return sum(1 for i in range(ticks) if i % every == phase)


def record(parts, path, seconds_: float) -> McapRecording:
    rec = McapRecording(parts, path)
    parts.robot.scheduler.run_for(seconds_)
    rec.close()
    return rec


def test_the_topics_are_the_documented_ones():
    assert set(TOPICS.values()) == set(EXPECTED_SCHEMAS)


def test_every_channel_of_the_robot_is_recorded_on_its_beat_with_foxglove_schemas(tmp_path):
    parts = fake_parts()
    record(parts, tmp_path / "run.mcap", 2.0)
    rec = read_mcap(tmp_path / "run.mcap")
    ticks = int(2.0 * RATE) + 1  # t = 0.0, 0.1, ..., 2.0
    # No tree: no pots, state, log or camera messages (their channels exist but stay empty).
    expected = {"/tf": ticks + 1, "/scan": ticks, "/plan": beats(ticks, *PLAN_BEAT) + 1,
                "/path": beats(ticks, *PLAN_BEAT) + 1, "/costmap/global": beats(ticks, *GRID_BEAT) + 1,
                "/map": beats(ticks, *GRID_BEAT) + 1}  # +1: the closing flush (a scan only when new)
    assert {t: n for t, n in rec.counts.items() if n} == expected
    for topic in expected:
        t = rec.topics[topic]
        assert (t.schema_name, t.schema_encoding, t.message_encoding) == EXPECTED_SCHEMAS[topic], topic


def test_timestamps_are_the_runtime_clock_not_the_wall(tmp_path):
    parts = fake_parts()
    record(parts, tmp_path / "run.mcap", 1.0)
    rec = read_mcap(tmp_path / "run.mcap")
    for topic, t in rec.topics.items():
        assert 0 <= min(t.log_times) and max(t.log_times) <= 1_000_000_000, topic
    tf = rec.decoded("/tf")
    assert [round(seconds(m["transforms"][0]["timestamp"]), 3) for m in tf[:3]] == [0.0, 0.1, 0.2]
    chain = [(x["parent_frame_id"], x["child_frame_id"]) for x in tf[0]["transforms"]]
    assert chain == [("map", "odom"), ("odom", "base_link"), ("base_link", "lidar"),
                     ("base_link", "front_camera_optical"), ("base_link", "wrist_camera_optical")]
    odom = tf[0]["transforms"][1]
    assert odom["translation"]["x"] == pytest.approx(1.0) and odom["rotation"]["z"] == pytest.approx(math.sin(0.15))
    scan = rec.decoded("/scan")[5]
    assert scan["frame_id"] == "lidar" and seconds(scan["timestamp"]) == pytest.approx(0.5)
    assert len(scan["ranges"]) == 360 and scan["end_angle"] == pytest.approx(2 * math.pi * 359 / 360)
    grid = rec.decoded("/costmap/global")[0]
    assert (grid["frame_id"], grid["column_count"], grid["row_stride"], len(grid["data"])) == ("map", 80, 80, 80 * 50)
    assert grid["fields"] == [{"name": "cost", "type": 1}]  # NumericType UINT8
    occupancy = rec.decoded("/map")[0]
    assert occupancy["fields"] == [{"name": "occupancy", "type": 2}]  # INT8: -1 unknown .. 100
    assert occupancy["pose"]["position"] == {"x": -1.0, "y": -1.0}
    plan = rec.decoded("/plan")[0]
    assert plan["frame_id"] == "map" and [p["position"].get("x", 0.0) for p in plan["poses"]] == [0.0, 1.0, 2.0]


def test_a_failing_source_is_logged_once_and_never_reaches_the_loop(tmp_path, caplog):
    parts = fake_parts()

    class Broken:
        @property
        def pose(self):
            raise RuntimeError("encoder glitch")

    parts.robot.base.odometry = Broken()
    with caplog.at_level(logging.ERROR, logger="mission.record.channels"):
        rec = record(parts, tmp_path / "run.mcap", 1.0)
    assert rec.channels.errors == {"tf": 11 + 1}  # every tick and the closing flush, nothing else
    assert len([r for r in caplog.records if r.name == "mission.record.channels"]) == 1
    counts = read_mcap(tmp_path / "run.mcap").counts
    assert counts.get("/tf", 0) == 0 and counts["/scan"] == 11  # the other channels go on


def test_nothing_is_built_while_nobody_listens():
    parts = fake_parts()

    class Watched:
        reads = 0

        @property
        def pose(self):
            Watched.reads += 1
            raise AssertionError("read with no sink")

    parts.robot.base.odometry = Watched()
    channels = PatrolChannels.of(parts).start()
    parts.robot.scheduler.run_for(1.0)
    assert channels.ticks == 11 and channels.errors == {} and Watched.reads == 0
    channels.close()
    assert channels.task not in parts.robot.scheduler.tasks


def test_the_first_tick_lands_on_the_lidar_beat():
    parts = fake_parts()
    parts.robot.scheduler.every("other", 7.0, lambda now: None)
    parts.robot.scheduler.run_until(0.43)  # between two lidar beats
    seen = []
    channels = PatrolChannels.of(parts)
    channels.tick = lambda now: seen.append(now)
    channels.start()
    parts.robot.scheduler.run_for(0.3)
    assert seen == pytest.approx([0.5, 0.6, 0.7])


def test_a_measured_scan_is_binned_to_equal_angles():
    uniform = LidarScan(0.0, np.arange(8, dtype=np.float32) * np.float32(math.pi / 4), np.arange(8, dtype=np.float32))
    start, end, ranges = uniform_scan(uniform)
    assert (start, end) == pytest.approx((0.0, 7 * math.pi / 4)) and list(ranges) == list(range(8))
    # measured angles: two returns nearest beam 1, none nearest beam 2
    angles = np.array([0.01, 0.80, 0.82, 2.40, 3.20, 4.00, 4.80, 5.60], dtype=np.float32)
    start, end, ranges = uniform_scan(LidarScan(0.0, angles, np.array([1, 2, 3, 4, 5, 6, 7, 8], dtype=np.float32)))
    assert (start, end) == pytest.approx((0.0, 7 * math.pi / 4))
    assert list(ranges) == [1, 2, np.inf, 4, 5, 6, 7, 8]


def rotation(q) -> np.ndarray:
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_quaternions_of_rotation_matrices_round_trip():
    rng = np.random.default_rng(1)
    for _ in range(50):
        m, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        m *= np.sign(np.linalg.det(m))
        assert rotation(matrix_quaternion(m)) == pytest.approx(m, abs=1e-9)
    for angle in (0.0, math.pi):  # the trace <= 0 branches
        m = np.diag([1.0, math.cos(angle), math.cos(angle)])
        assert rotation(matrix_quaternion(m)) == pytest.approx(m, abs=1e-9)


def test_the_wrist_optical_frame_looks_along_the_camera_axis_with_its_right_horizontal():
    axis = np.array([0.5, 0.5, -0.7])
    pan = math.atan2(axis[1], axis[0])
    r = rotation(optical_rotation(axis, pan))
    assert r[:, 2] == pytest.approx(axis / np.linalg.norm(axis))
    assert r[2, 0] == pytest.approx(0.0, abs=1e-12) and r[2, 1] < 0  # image right is level, image down is down


def test_pot_colours_follow_the_report():
    pots = [SimpleNamespace(id=i) for i in ("P01", "P02", "P03", "P04", "P05")]
    report = SimpleNamespace(pots={"P01": {"status": "inspected"}, "P02": {"status": "inspected"},
                                   "P03": {"status": "failed"}},
                             anomalies=[{"kind": "bug", "pot": "P02", "detail": ""}], outcome=None)
    visits = {"P04": SimpleNamespace(attempts=1), "P05": SimpleNamespace(attempts=0)}
    tree = SimpleNamespace(mission=SimpleNamespace(pots=pots), report=report, visits=visits)
    assert pot_statuses(tree) == {"P01": "inspected", "P02": "anomaly", "P03": "failed", "P04": "active",
                                  "P05": "pending"}
    report.outcome = "aborted"
    assert pot_statuses(tree)["P04"] == pot_statuses(tree)["P05"] == "skipped"


class Walkers:
    """A ``robot.people`` stand-in: ``current()`` is what ``tracks`` holds now, ``confident()``
    the ones in ``walked``."""

    def __init__(self, tracks=(), walked=()):
        self.tracks, self.walked = tuple(tracks), set(walked)

    def current(self):
        return self.tracks

    def confident(self):
        return tuple(p for p in self.tracks if p.id in self.walked)


def meta(entity) -> dict[str, str]:
    return {kv["key"]: kv["value"] for kv in entity["metadata"]}


def test_a_tracked_person_is_recorded_with_id_speed_and_confidence_and_leaves_when_the_track_ends(tmp_path):
    parts = fake_parts()
    walker, box = Person(7, 2.0, 1.0, 0.6, 0.8, 0.25, 0.9), Person(8, -1.0, 0.5, 0.0, 0.0, 0.15, 0.6)
    parts.robot.people = Walkers([walker, box], walked={7})
    rec = McapRecording(parts, tmp_path / "run.mcap")
    sched = parts.robot.scheduler
    sched.run_for(0.45)  # ticks at 0.0 .. 0.4: five updates with both
    parts.robot.people.tracks = ()  # the tracker lost them
    sched.run_for(0.5)  # one emptying update at 0.5, then nothing
    rec.close()
    mcap = read_mcap(tmp_path / "run.mcap")
    updates = mcap.decoded("/people")
    assert len(updates) == 6 and mcap.counts["/people"] == 6
    assert [round(t / 1e8) for t in mcap.topics["/people"].log_times] == [0, 1, 2, 3, 4, 5]
    first = updates[0]
    assert [d["type"] for d in first["deletions"]] == [1]  # ALL: a dropped track does not linger
    walking, standing = first["entities"]
    assert (walking["id"], walking["frame_id"]) == ("person-7", "odom")
    assert meta(walking) == {"id": "7", "speed": "1.00", "confidence": "0.90", "vx": "0.60", "vy": "0.80",
                             "walked": "true"}
    assert meta(standing)["walked"] == "false" and meta(standing)["speed"] == "0.00"
    body = walking["cylinders"][0]
    assert (body["pose"]["position"]["x"], body["pose"]["position"]["y"]) == pytest.approx((2.0, 1.0))
    assert body["size"]["x"] == pytest.approx(0.5)
    arrow = walking["arrows"][0]
    assert arrow["shaft_length"] == pytest.approx(1.0)  # a second of walking
    q = arrow["pose"]["orientation"]
    assert 2 * math.atan2(q["z"], q["w"]) == pytest.approx(math.atan2(0.8, 0.6))
    assert "arrows" not in standing  # standing: no arrow
    assert walking["texts"][0]["text"] == "person 7 1.0 m/s 90%"
    assert "entities" not in updates[-1] and [d["type"] for d in updates[-1]["deletions"]] == [1]


@pytest.mark.parametrize("people", [None, Walkers()], ids=["no tracker", "nobody tracked"])
def test_no_people_no_people_messages(tmp_path, people):
    parts = fake_parts()
    parts.robot.people = people
    record(parts, tmp_path / "run.mcap", 0.5)
    counts = read_mcap(tmp_path / "run.mcap").counts
    assert counts["/tf"] == 7 and counts.get("/people", 0) == 0  # recorded, but nothing on /people
