"""The link against a real sim runtime over real Zenoh sessions on loopback: the token rule,
fuzzed queries that leave the runtime unharmed, a console that vanishes mid-teleop, and two
consoles that see the same robot. Each test has a runtime of its own (tests/link/sim_service.py)."""
from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
import zenoh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mission.link.server import session_config
from mission.link.telemetry import TOPICS
from mission.link.wire import cmd_key
from tests.link.sim_service import TOKEN, client, runtime, wait_for  # noqa: F401  (runtime: the fixture)

pytestmark = pytest.mark.slow


def test_unauthorised_commands_are_refused_and_anyone_may_stop_the_robot(runtime):
    service, endpoint = runtime.service, runtime.endpoint
    stranger, operator = client(endpoint, "guess"), client(endpoint)
    try:
        assert "operator token" in stranger.send("mission_start")
        assert "operator token" in stranger.send("teleop", vx=0.2)
        assert service.run is None and stranger.send("estop", engaged=True) is None
        assert wait_for(lambda: operator.view().estop_engaged and operator.view().mux_source == "estop")
        assert "operator token" in stranger.send("estop", engaged=False)
        assert operator.send("estop", engaged=False) is None
        assert wait_for(lambda: not operator.view().estop_engaged)
        assert "no mission is running" in operator.send("pause")
    finally:
        stranger.close()
        operator.close()


def test_two_consoles_see_the_same_robot_and_mission(runtime):
    service, endpoint = runtime.service, runtime.endpoint
    a, b = client(endpoint), client(endpoint)
    try:
        assert a.send("mission_start") is None
        assert "still running" in b.send("mission_start")
        assert wait_for(lambda: a.view().mission_state == "running" and b.view().mission_state == "running")
        assert wait_for(lambda: a.view().grid is not None and b.view().grid is not None and len(a.view().pots) == 12)
        assert wait_for(lambda: a.view().tree and b.view().tree)
        assert wait_for(lambda: 0.5 < a.view().charge <= 1.0)  # the patrol's energy budget, on the console
        assert a.view().heading_home == ""
        assert wait_for(lambda: {"state", "nav", "mission", "tree", "pots", "status", "scan", "map", "costmap"} <= set(a.received))
        assert set(a.received) <= set(TOPICS)  # every topic documented in mission.link.telemetry
        assert wait_for(lambda: abs(a.view().t - b.view().t) <= 0.2)  # the same state messages, as they arrive
        va, vb = a.view(), b.view()
        assert [p.id for p in va.pots] == [p.id for p in vb.pots] and va.mission_name == vb.mission_name
        assert va.grid.data.shape == vb.grid.data.shape
        assert b.send("pause") is None
        assert wait_for(lambda: a.view().mission_state == "paused")
        assert a.send("resume") is None
        assert wait_for(lambda: b.view().mission_state == "running")
        jpeg = a.snapshot("front")
        assert jpeg is not None and jpeg[:2] == b"\xff\xd8"
        assert b.send("mission_abort") is None
        assert wait_for(lambda: a.view().mission_state == "done" and a.view().mission_outcome == "aborted")
        assert (Path(service.runs) / "default-patrol-1" / "report.json").is_file()  # this runtime's first patrol
    finally:
        a.close()
        b.close()


def test_a_console_that_vanishes_mid_teleop_stops_the_robot_within_the_mux_timeout(runtime):
    service, endpoint, probe = runtime.service, runtime.endpoint, runtime.probe
    c = client(endpoint)
    assert c.send("mission_start") is None
    for _ in range(15):  # hold the stick for ~0.75 s
        assert c.send("teleop", vx=0.0, vy=0.1, wz=0.0) is None
        time.sleep(0.05)
    assert wait_for(lambda: service.robot.base.source == "manual", 2.0)
    last = service.robot.mux.last("manual")[0]
    c.session.close()  # the console dies: no goodbye, no zero twist
    assert wait_for(lambda: probe and probe[-1][0] > last + 1.0)
    after = [(t, src) for t, src in probe if t > last]
    stopped = next(t for t, src in after if src != "manual")
    # the source is live until exactly its timeout after its last message; the wheels are
    # zeroed on the first control tick after that
    timeout, period = service.config.hw.mux.sources["manual"].timeout, 1.0 / service.config.hw.base.control_rate
    assert timeout < stopped - last <= timeout + period + 1e-6
    assert all(src != "manual" for t, src in after if t >= stopped)
    # the mission never stopped: autonomy has the wheels back
    assert service.run is not None and wait_for(lambda: service.robot.base.source == "auto")
    c2 = client(endpoint)
    try:
        assert c2.send("mission_abort") is None
    finally:
        c2.close()


def test_map_save_over_the_link(runtime, tmp_path):
    from lupin.cli import main
    from nav.map_io import load_map

    service, endpoint = runtime.service, runtime.endpoint
    assert main(["map", "save", "--connect", endpoint, "-o", str(tmp_path / "live.yaml")]) == 0
    saved, held = load_map(tmp_path / "live.yaml"), service.nav.localisation.occupancy
    assert saved.resolution == held.resolution and (saved.occupancy == 100).sum() > 100


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(["teleop", "arm_preset", "gripper", "estop", "mission_start", "x", "snapshot"]),
       payload=st.binary(max_size=64) | st.dictionaries(st.sampled_from(["token", "vx", "engaged", "name", "action", "mission"]),
                                                       st.none() | st.booleans() | st.floats() | st.text(max_size=6),
                                                       max_size=4).map(lambda d: json.dumps(d).encode()))
def test_fuzzed_queries_are_refused_without_harming_the_runtime(runtime, fuzz_session, name, payload):
    service, probe = runtime.service, runtime.probe
    replies = list(fuzz_session.get(cmd_key("mirte", name), payload=payload, timeout=3.0))
    assert len(replies) == 1
    reply = replies[0]
    if reply.err is not None:
        assert json.loads(reply.err.payload.to_bytes())["error"]
    else:  # only the stop is open to anyone
        assert name == "estop" and json.loads(payload).get("engaged") is True
        release = json.dumps({"token": TOKEN, "engaged": False})  # the operator puts it back
        assert list(fuzz_session.get(cmd_key("mirte", "estop"), payload=release, timeout=3.0))[0].err is None
        assert wait_for(lambda: not service.robot.estop.engaged())
    before = probe[-1][0]
    assert wait_for(lambda: probe[-1][0] > before)  # the control loop still beats


@pytest.fixture
def fuzz_session(runtime):
    """A bare Zenoh session on the runtime's endpoint, for queries no client would send."""
    session = zenoh.open(session_config("connect", runtime.endpoint))
    yield session
    session.close()
