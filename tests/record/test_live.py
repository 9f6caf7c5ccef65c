"""The live Foxglove server: it starts on a free port, advertises the same channels as a
recording, streams them (and the runtime clock) to a subscribed client, and stops."""
from __future__ import annotations

import json
import socket
import struct
import time

from websockets.sync import client as ws_client

from mission.record.live import serve_foxglove
from mission.record.mcap_file import McapRecording
from tests.record.fixtures import fake_parts, read_mcap
from tests.record.test_channels import EXPECTED_SCHEMAS


def listening(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(1.0)
        return s.connect_ex(("127.0.0.1", port)) == 0


def test_the_server_starts_on_a_free_port_and_stops():
    parts = fake_parts()
    server = serve_foxglove(parts, port=0)
    try:
        assert server.port > 0 and listening(server.port)
        assert {"foxglove", "foxglove.time"} <= set(parts.robot.scheduler.tasks)
    finally:
        server.stop()
    assert not listening(server.port)
    assert not {"foxglove", "foxglove.time"} & set(parts.robot.scheduler.tasks)
    server.stop()  # twice is harmless


def test_a_client_sees_the_channels_and_sim_time_messages(tmp_path):
    parts = fake_parts()
    server = serve_foxglove(parts, port=0)
    recording = McapRecording(parts, tmp_path / "run.mcap", channels=server.channels)  # both sinks, one task
    try:
        with ws_client.connect(f"ws://127.0.0.1:{server.port}", subprotocols=["foxglove.sdk.v1"],
                               open_timeout=10) as ws:
            channels: dict[str, dict] = {}
            while set(channels) != set(EXPECTED_SCHEMAS):
                msg = json.loads(ws.recv(timeout=10))
                if msg["op"] == "serverInfo":
                    assert "time" in msg["capabilities"]
                    assert msg["name"] == f"lupin {parts.robot.config.link.robot}"  # whose, in a fleet
                elif msg["op"] == "advertise":
                    channels.update({c["topic"]: c for c in msg["channels"]})
            assert channels["/tf"]["schemaName"] == "foxglove.FrameTransforms"
            assert channels["/mission/state"]["encoding"] == "json"
            ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": channels["/tf"]["id"]}]}))
            data, times = [], []
            deadline = time.monotonic() + 20  # test-harness wait on the server's threads, not a timing assertion
            while (len(data) < 5 or not times) and time.monotonic() < deadline:
                parts.robot.scheduler.run_for(0.1)
                try:
                    while True:
                        frame = ws.recv(timeout=0.05)
                        if isinstance(frame, bytes) and frame[0] == 1:  # message data
                            data.append(struct.unpack_from("<IQ", frame, 1))
                        elif isinstance(frame, bytes) and frame[0] == 2:  # time
                            times.append(struct.unpack_from("<Q", frame, 1)[0])
                except TimeoutError:
                    pass
        now = round(parts.robot.scheduler.clock.now() * 1e9)
        assert {sub for sub, _ in data} == {7}
        assert len(data) >= 5 and times
        assert all(t <= now for _, t in data) and all(t <= now for t in times)  # sim ns, not the wall's epoch
        assert all(t % 100_000_000 == 0 for _, t in data)  # on the 10 Hz beat
    finally:
        recording.close()
        server.stop()
    assert read_mcap(tmp_path / "run.mcap").counts["/tf"] == server.channels.ticks + 1  # same ticks, + the flush
