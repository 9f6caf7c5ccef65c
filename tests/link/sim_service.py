"""A real-time sim service with its link server on loopback, for the tests that talk to a
running robot over the link (tests/link/test_link_sim.py, tests/tui/test_console_sim.py).

``runtime`` is function-scoped: every test gets a robot fresh from the dock (no mission run
yet, the e-stop released, SLAM's first map, an empty runs directory), so no test depends on
what another left behind and each passes alone and in any order. A fresh one costs about half
a second of start-up; the tests themselves wait on the robot's own pace (seconds each), so
sharing one would save little and cost the tests their independence.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from mission.jobs.serve import Service, run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.client import LinkClient
from mission.link.server import LinkServer, free_endpoint
from mission.runtime.config import LupinConfig, with_overrides
from sim.world import load_default_world

TOKEN = "operator-token"


def wait_for(cond, timeout=10.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return True
        time.sleep(0.02)
    return False


@dataclass
class SimLink:
    """The service, its link server and endpoint; ``probe`` holds (runtime time, wheel owner)
    after every control tick."""

    service: Service
    server: LinkServer
    endpoint: str
    probe: list[tuple[float, str]] = field(default_factory=list)

    def __repr__(self) -> str:  # hypothesis prints the fixture of a failing example
        return f"SimLink({self.endpoint})"


@pytest.fixture
def runtime(tmp_path: Path):
    """A real-time sim service with its link server, stepping on its own thread, once its
    control loop beats."""
    # a real-time runtime on a loaded machine (two of them under xdist) can fall a few seconds
    # behind: the tests judge what a command does, not how fast it is answered
    config = with_overrides(LupinConfig(), {"sim": {"realtime": True}, "link": {"command_timeout": 8.0}})
    service = start_sim_service(load_default_world(), config, tmp_path / "runs", time.perf_counter)
    endpoint = free_endpoint()
    link = SimLink(service, LinkServer(service, config.link, TOKEN, endpoint), endpoint)
    service.robot.scheduler.every("test.probe", config.hw.base.control_rate,
                                  lambda now: link.probe.append((round(now - 1e-4, 6), service.robot.base.source)),
                                  offset=1e-4)
    stop = threading.Event()
    thread = threading.Thread(target=run_service, args=(service, stop, link.server.close), daemon=True)
    thread.start()
    try:
        assert wait_for(lambda: link.probe), "the runtime never ticked"
        yield link
    finally:
        stop.set()
        thread.join(20)


def client(endpoint: str, token: str = TOKEN) -> LinkClient:
    c = LinkClient(endpoint, "mirte", clock=time.monotonic, token=token, timeout=10.0)
    assert wait_for(lambda: c.view().connected), "no telemetry"
    return c
