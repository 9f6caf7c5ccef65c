"""The console's link goes stale on the console's clock: a real Zenoh session on loopback plays
the robot, and the client's clock is the test's, so staleness is judged without waiting."""
from __future__ import annotations

import zenoh

from mission.link.client import STALE_S, LinkClient
from mission.link.server import free_endpoint, session_config
from mission.link.wire import tel_key
from tests.link.sim_service import wait_for


def test_the_view_is_disconnected_once_no_telemetry_came_for_the_stale_time_on_the_consoles_clock():
    endpoint = free_endpoint()
    robot = zenoh.open(session_config("listen", endpoint))
    now = [100.0]
    client = LinkClient(endpoint, "mirte", clock=lambda: now[0])
    try:
        assert not client.view().connected  # nothing heard yet
        assert wait_for(lambda: (robot.put(tel_key("mirte", "log"), b"hello"), client.received.get("log"))[1])
        assert client.view().connected and client.view().log[-1] == "hello"
        now[0] += STALE_S * 0.9
        assert client.view().connected
        now[0] += STALE_S * 0.2  # past the stale time since the last message, and nothing since
        assert not client.view().connected
        heard = client.received["log"]
        assert wait_for(lambda: (robot.put(tel_key("mirte", "log"), b"again"), client.received["log"] > heard)[1])
        assert client.view().connected  # a message heard now connects it again
    finally:
        client.close()
        robot.close()
