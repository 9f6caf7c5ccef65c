"""The fleet as a user starts it: `lupin router --certs`, `lupin serve --robot r1 --connect tls/...
--certs`, a console as ``ops``; a robot killed (SIGKILL: no goodbye) is off the console's list
within a second."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from fleet.certs import member_files
from mission.link.fleet_link import FleetLink
from mission.link.session import free_endpoint
from tests.fleet.conftest import wait_for

pytestmark = pytest.mark.slow
LUPIN = str(Path(sys.executable).parent / "lupin")


def _start(args: list[str], until: str, env=None) -> subprocess.Popen:
    proc = subprocess.Popen([LUPIN, *args], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env={**os.environ, **(env or {})})
    while until not in (line := proc.stdout.readline()):
        assert line and proc.poll() is None, f"lupin {args[0]} did not start"
    return proc


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()


def test_router_serve_and_console_from_the_command_line_and_a_killed_robot_goes_within_a_second(certs, tmp_path):
    endpoint = free_endpoint("tls")
    router = _start(["router", "--listen", endpoint, "--certs", str(certs)], "listening on")
    robot = None
    try:
        robot = _start(["serve", "--robot", "r1", "--connect", endpoint, "--certs", str(certs), "--runs", str(tmp_path)],
                       "through the router at", env={"LUPIN_LINK__COMMAND_TIMEOUT": "8"})
        console = FleetLink(endpoint, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=10.0)
        try:
            assert wait_for(lambda: console.robots() == ["r1"], 10)
            assert wait_for(lambda: console.view().connected and console.view().controllers, 30)
            assert console.send("arm_preset", name="tuck") is None  # no token: the router says who commands
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
        _stop(router)
    assert router.returncode == 0
