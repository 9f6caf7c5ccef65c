"""Builders for the recording tests: tiny stand-in parts (a robot and a navigator that only
answer what the channels read), and an MCAP reader that decodes what Foxglove would.

``read_mcap`` reads a recording with the ``mcap`` library, the way any other tool would, and
decodes protobuf messages against the schema the file itself carries (its FileDescriptorSet),
with a minimal wire-format reader: no protobuf package is needed, and a field the SDK named
differently from what we assert would show up as missing rather than be read by position.
"""
from __future__ import annotations

import io
import json
import math
import struct
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from arm.presets import PRESETS
from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from mission.runtime.config import LupinConfig
from mission.runtime.scheduler import Scheduler
from nav.costmap.grid import CostGrid
from nav.occupancy import OccupancyMap
from sim.clock import SimClock


# --- stand-in parts ---------------------------------------------------------------------------

class FakeLidar:
    """A new 360-point revolution every 0.1 s of the clock: a 2 m circle."""

    def __init__(self, clock: SimClock):
        self.clock = clock
        self.angles = (np.arange(360) * (2 * math.pi / 360)).astype(np.float32)

    def latest_scan(self) -> LidarScan:
        k = math.floor(self.clock.now() * 10 + 1e-9)
        return LidarScan(k / 10, self.angles, np.full(360, 2.0, dtype=np.float32))


def fake_parts() -> SimpleNamespace:
    """``robot`` and ``nav`` as the channels read them (no tree), on a sim clock at 0."""
    clock = SimClock()
    odometry = SimpleNamespace(pose=Pose2D(1.0, 0.5, 0.3))
    robot = SimpleNamespace(config=LupinConfig(), scheduler=Scheduler(clock),
                            base=SimpleNamespace(odometry=odometry),
                            hal=SimpleNamespace(lidar=FakeLidar(clock)),
                            arm=SimpleNamespace(joint_vector=lambda: np.array(PRESETS["inspect"])))
    occupancy = OccupancyMap(np.full((40, 60), -1, dtype=np.int8), 0.05, -1.0, -1.0)
    localisation = SimpleNamespace(map_to_odom=lambda: Pose2D(0.1, 0.0, 0.0), occupancy=occupancy)
    nav = SimpleNamespace(localisation=localisation, map_pose=lambda: Pose2D(1.1, 0.5, 0.3),
                          path=np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]]),
                          global_costmap=SimpleNamespace(grid=CostGrid.filled(80, 50, 0.05, -2.0, -1.0, 255)))
    return SimpleNamespace(robot=robot, nav=nav, tree=None)


# --- protobuf wire format -----------------------------------------------------------------------

def _varint(buf: bytes, i: int) -> tuple[int, int]:
    shift = value = 0
    while True:
        b = buf[i]
        i += 1
        value |= (b & 0x7F) << shift
        if b < 0x80:
            return value, i
        shift += 7


def wire_fields(buf: bytes):
    """(field number, wire type, value): ints for varint and fixed, bytes for length-delimited."""
    i = 0
    while i < len(buf):
        key, i = _varint(buf, i)
        number, wire = key >> 3, key & 7
        if wire == 0:
            value, i = _varint(buf, i)
        elif wire == 1:
            value, i = buf[i:i + 8], i + 8
        elif wire == 5:
            value, i = buf[i:i + 4], i + 4
        elif wire == 2:
            n, i = _varint(buf, i)
            value, i = buf[i:i + n], i + n
        else:
            raise ValueError(f"wire type {wire} not supported")
        yield number, wire, value


_MESSAGE, _STRING, _BYTES, _REPEATED = 11, 9, 12, 3
_FIXED = {1: "<d", 2: "<f", 6: "<Q", 7: "<I", 15: "<i", 16: "<q"}
"""FieldDescriptorProto types with a fixed width: double, float, fixed64, fixed32, sfixed32, sfixed64."""


@dataclass
class ProtoSchemas:
    """Message layouts from a FileDescriptorSet: full name -> field number -> (name, type,
    type name, repeated)."""

    messages: dict[str, dict[int, tuple[str, int, str, bool]]] = field(default_factory=dict)

    def add(self, descriptor_set: bytes) -> None:
        for num, _, file in wire_fields(descriptor_set):
            if num != 1:
                continue
            package = next((v.decode() for n, _, v in wire_fields(file) if n == 2), "")
            for n, _, msg in wire_fields(file):
                if n == 4:
                    self._message(msg, package)

    def _message(self, msg: bytes, scope: str) -> None:
        name = next(v.decode() for n, _, v in wire_fields(msg) if n == 1)
        full = f"{scope}.{name}" if scope else name
        fields = {}
        for n, _, v in wire_fields(msg):
            if n == 2:  # FieldDescriptorProto: 1 name, 3 number, 4 label, 5 type, 6 type_name
                f = {k: val for k, _, val in wire_fields(v)}
                fields[f[3]] = (f[1].decode(), f[5], f.get(6, b"").decode().lstrip("."), f.get(4) == _REPEATED)
            elif n == 3:
                self._message(v, full)
        self.messages[full] = fields

    def decode(self, type_name: str, buf: bytes) -> dict:
        layout = self.messages[type_name]
        out: dict = {}
        for number, wire, value in wire_fields(buf):
            if number not in layout:
                continue
            name, kind, sub, repeated = layout[number]
            if kind == _MESSAGE:
                values = [self.decode(sub, value)]
            elif kind in _FIXED:
                fmt = _FIXED[kind]
                if wire == 2:  # packed
                    values = [v for (v,) in struct.iter_unpack(fmt, value)]
                else:
                    values = [struct.unpack(fmt, value)[0]]
            elif kind == _STRING:
                values = [value.decode()]
            elif kind == _BYTES:
                values = [bytes(value)]
            else:
                values = [value]
            if repeated:
                out.setdefault(name, []).extend(values)
            else:
                out[name] = values[0]
        return out


# --- an MCAP file as a reader sees it ----------------------------------------------------------

@dataclass
class Topic:
    schema_name: str
    schema_encoding: str
    message_encoding: str
    log_times: list[int] = field(default_factory=list)
    payloads: list[bytes] = field(default_factory=list)


@dataclass
class Recording:
    topics: dict[str, Topic]
    counts: dict[str, int]
    """Per-topic message counts from the file's summary statistics."""
    protos: ProtoSchemas
    profile: str

    def decoded(self, topic: str) -> list[dict]:
        t = self.topics[topic]
        if t.message_encoding == "json":
            return [json.loads(p) for p in t.payloads]
        return [self.protos.decode(t.schema_name, p) for p in t.payloads]


def read_mcap(source: Path | bytes) -> Recording:
    from mcap.reader import make_reader

    stream = io.BytesIO(source) if isinstance(source, bytes) else open(source, "rb")
    with stream:
        reader = make_reader(stream)
        profile = reader.get_header().profile
        summary = reader.get_summary()
        counts = {ch.topic: summary.statistics.channel_message_counts.get(cid, 0)
                  for cid, ch in summary.channels.items()}
        topics: dict[str, Topic] = {}
        protos = ProtoSchemas()
        for schema, channel, message in reader.iter_messages(log_time_order=True):
            if channel.topic not in topics:
                topics[channel.topic] = Topic(schema.name if schema else "", schema.encoding if schema else "",
                                              channel.message_encoding)
                if schema is not None and schema.encoding == "protobuf":
                    protos.add(schema.data)
            topics[channel.topic].log_times.append(message.log_time)
            topics[channel.topic].payloads.append(message.data)
    return Recording(topics, counts, protos, profile)


def seconds(ts: dict) -> float:
    """A decoded google.protobuf.Timestamp (absent fields are zero) in seconds."""
    return ts.get("seconds", 0) + ts.get("nanos", 0) / 1e9
