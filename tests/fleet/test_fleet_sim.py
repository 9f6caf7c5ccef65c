"""Real runtimes in a fleet: two simulated robots join the TLS router under their own
certificates (``LinkServer(connect=...)``), and a console (``FleetLink`` as ``ops``) commands each;
a robot's own session stops another robot but cannot release it; the fleet e-stop stops both; a
robot whose link goes is off the console's list within a second, and a console started again
finds the robots."""
from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest

from fleet.certs import member_files
from mission.jobs.serve import run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.client import LinkClient
from mission.link.fleet_link import FleetLink
from mission.link.server import LinkServer
from mission.runtime.config import LupinConfig, with_overrides
from sim.world import load_default_world
from tests.fleet.conftest import wait_for

pytestmark = pytest.mark.slow


class FleetRobot:
    """A sim service (real time, unless ``realtime`` False) of ``world`` (default the built-in
    one) whose link joins the router as ``name``."""

    def __init__(self, name: str, endpoint: str, certs: Path, runs: Path, world=None, realtime: bool = True):
        config = with_overrides(LupinConfig(), {"sim": {"realtime": realtime},
                                                "link": {"robot": name, "command_timeout": 8.0}})
        self.service = start_sim_service(world or load_default_world(), config, runs, time.perf_counter)
        self.server = LinkServer(self.service, config.link, None, connect=endpoint, tls=member_files(certs, name))
        self._stop = threading.Event()
        self._thread = threading.Thread(target=run_service, args=(self.service, self._stop, self.server.close), daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join(30)


@pytest.fixture
def two_robots(router, certs, tmp_path):
    robots = {n: FleetRobot(n, router, certs, tmp_path / n) for n in ("r1", "r2")}
    try:
        yield robots
    finally:
        for r in robots.values():
            r.close()


def _views(console: FleetLink, robot: str):
    return console.client(robot).view()


def test_a_console_commands_each_robot_and_a_robot_stops_another_but_cannot_release_it(router, certs, two_robots):
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=10.0)
    try:
        assert wait_for(lambda: console.robots() == ["r1", "r2"], 10)
        assert console.view().robot == "r1" and console.view().fleet == ["r1", "r2"]
        assert wait_for(lambda: all(_views(console, r).connected for r in ("r1", "r2")), 20)
        assert wait_for(lambda: [o.robot for o in console.view().others] == ["r2"], 5)  # the fleet view
        # r1, shown first; held as a key is (a twist lives 0.5 s on the manual source)
        assert wait_for(lambda: console.send("teleop", wz=0.3) is None and _views(console, "r1").mux_source == "manual", 10)
        assert _views(console, "r2").mux_source != "manual"
        assert console.select(1) == "r2" and console.view().robot == "r2"
        assert console.send("arm_preset", name="tuck") is None
        assert "unknown" in console.send("arm_preset", name="wave").lower()  # r2's own runtime answered

        r2_session = two_robots["r2"].server.session  # what r2's runtime holds: its certificate's rights
        r2_as_client = LinkClient(None, "r1", clock=time.monotonic, timeout=2.0, session=r2_session)
        assert r2_as_client.stop() is None
        assert wait_for(lambda: _views(console, "r1").estop_engaged, 5)
        assert "no answer" in r2_as_client.send("estop", engaged=False)  # releasing is a console's
        time.sleep(0.5)
        assert _views(console, "r1").estop_engaged and not _views(console, "r2").estop_engaged
        console.select(0)
        assert console.send("estop", engaged=False) is None
        assert wait_for(lambda: not _views(console, "r1").estop_engaged, 5)

        assert console.stop_fleet() == ["r1", "r2"]
        assert wait_for(lambda: all(_views(console, r).estop_engaged for r in ("r1", "r2")), 5)
        assert wait_for(lambda: all(not two_robots[r].service.robot.base.last_duties.any() for r in ("r1", "r2")), 2)
        r2_as_client.close()
    finally:
        console.close()


def test_a_robot_gone_leaves_the_list_within_a_second_and_a_restarted_console_finds_the_rest(router, certs, two_robots):
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"))
    try:
        assert wait_for(lambda: console.robots() == ["r1", "r2"], 10)
        two_robots["r2"].close()  # its runtime stops (a killed one: tests/fleet/test_fleet_cli.py)
        assert wait_for(lambda: console.robots() == ["r1"], 1.0), "r2's going took over a second to show"
    finally:
        console.close()
    again = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"))
    try:
        assert wait_for(lambda: again.robots() == ["r1"], 1.0)
        assert wait_for(lambda: again.view().robot == "r1" and again.view().connected, 5)
    finally:
        again.close()
