"""The fleet as a user starts it: `lupin router --certs`, `lupin serve --robot r1 --connect tls/...
--certs`, a console as ``ops``; a robot that falls silent (SIGSTOP: its socket open, nothing on
it) and one killed (SIGKILL: no goodbye) are off the console's list within a second."""
from __future__ import annotations

import os
import signal
import time

import pytest

from fleet.certs import member_files
from lupin.bench.fleet import start_lupin
from lupin.cli.console import stop_child
from mission.link.fleet_link import FleetLink
from mission.link.session import free_endpoint
from tests.fleet.conftest import wait_for

pytestmark = pytest.mark.slow


def test_router_serve_and_console_from_the_command_line_and_a_killed_robot_goes_within_a_second(certs, tmp_path):
    endpoint = free_endpoint("tls")
    router = start_lupin(["router", "--listen", endpoint, "--certs", str(certs)], "listening on")
    robot = None
    try:
        robot = start_lupin(["serve", "--robot", "r1", "--connect", endpoint, "--certs", str(certs), "--runs", str(tmp_path)],
                            "through the router at", env={"LUPIN_LINK__COMMAND_TIMEOUT": "8"})
        console = FleetLink(endpoint, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=10.0)
        try:
            assert wait_for(lambda: console.robots() == ["r1"], 10)
            assert wait_for(lambda: console.view().connected and console.view().controllers, 30)
            assert console.send("arm_preset", name="tuck") is None  # no token: the router says who commands
            os.kill(robot.pid, signal.SIGSTOP)  # hung, or off the network: its socket stays open, silent
            try:
                assert wait_for(lambda: console.robots() == [], 1.0), "a silent robot stayed listed over a second"
            finally:
                os.kill(robot.pid, signal.SIGCONT)
            assert wait_for(lambda: console.robots() == ["r1"], 10)  # back when it speaks again
            robot.kill()
            t0 = time.monotonic()
            assert wait_for(lambda: console.robots() == [], 1.0), "a killed robot stayed listed over a second"
            assert time.monotonic() - t0 < 1.0
        finally:
            console.close()
    finally:
        if robot is not None:
            robot.kill()
            robot.wait(timeout=30)
        stop_child(router)
    assert router.returncode == 0
