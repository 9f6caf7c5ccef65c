"""Issue 33's soak: three robots and a console through one router for 10 minutes of sim time,
nothing lost on the e-stop channel.

The three runtimes are ``lupin fleet sim --fast``'s (``mission.jobs.fleet_sim``: one greenhouse,
a runtime each in lock-step, each link joined to the TLS router with access control under its
own certificate), so ten minutes of robot time take about a minute and a half on 2 cores. Every
``EVERY_S`` of robot time a stop goes out in turn as another robot's stop key (a robot may stop
a robot), the console's ``estop`` command and the fleet stop, each to robots turning on the
console's teleop (the manual source held live for the run, so a stop has wheels to stop). A
stop counts when its query was answered, the robot's own telemetry shows it engaged and its
wheels' duties are all zero (read off the runtime: judging only); the console then releases
it and turns it again before the next. ``lupin bench fleet.soak`` is the same channel over
ten minutes of wall time, with the robots as processes.
"""
from __future__ import annotations

import threading
import time

import pytest

from fleet.certs import member_files
from mission.jobs.fleet_sim import fleet_world, run_fleet, start_fleet_sim
from mission.link.client import LinkClient
from mission.link.fleet_link import FleetLink
from mission.runtime.config import LupinConfig, with_overrides
from tests.fleet.conftest import wait_for

pytestmark = pytest.mark.slow

ROBOTS = ["r1", "r2", "r3"]
SOAK_S = 600.0
"""Robot time, s: the issue's ten minutes."""
EVERY_S = 2.0
"""Robot time between stops, s: 300 stops, 500 robots stopped."""
TURN = 0.6
"""The console's turn, rad/s: every stop finds its robot's wheels turning."""
WAIT_S = 20.0
"""Wall seconds any one step may take before it counts as lost (a loaded machine is slow, not lossy)."""


def _config() -> LupinConfig:
    manual_for_the_run = {"joy": {"priority": 100, "timeout": 0.3}, "manual": {"priority": 50, "timeout": 2 * SOAK_S},
                          "auto": {"priority": 10, "timeout": 0.5}}
    return with_overrides(LupinConfig(), {"sim": {"realtime": False}, "link": {"command_timeout": WAIT_S},
                                          "hw": {"mux": {"sources": manual_for_the_run}}})


def test_three_robots_and_a_console_for_ten_minutes_lose_no_stop(router, certs, tmp_path):
    fleet = start_fleet_sim(fleet_world(len(ROBOTS)), _config(), ROBOTS, tmp_path, time.perf_counter)
    fleet.join(router, lambda name: member_files(certs, name), None)
    sessions = {link.config.robot: link.session for link in fleet.links}
    stop = threading.Event()
    stepping = threading.Thread(target=run_fleet, args=(fleet, stop), daemon=True)
    stepping.start()
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=WAIT_S)
    # robot r(k+1)'s own session stops r(k): what its certificate allows
    peers = {r: LinkClient(None, r, clock=time.monotonic, timeout=WAIT_S, session=sessions[ROBOTS[(i + 1) % 3]])
             for i, r in enumerate(ROBOTS)}
    lost: list[str] = []
    stopped = attempted = 0

    def robot_now() -> float:
        return min(s.now for s in fleet.services.values())

    def turning(r: str) -> bool:
        return bool(fleet.services[r].robot.base.last_duties.any())

    def halted(r: str) -> bool:
        return console.client(r).view().estop_engaged and not turning(r)

    try:
        assert wait_for(lambda: console.robots() == ROBOTS and all(console.client(r).view().connected for r in ROBOTS), 60)
        start = robot_now()
        for k in range(round(SOAK_S / EVERY_S)):
            while robot_now() < start + k * EVERY_S:
                time.sleep(0.005)
            how, target = ("peer", "console", "fleet")[k % 3], ROBOTS[k % 3]
            targets = ROBOTS if how == "fleet" else [target]
            for r in targets:
                assert console.client(r).send("teleop", wz=TURN) is None
                assert wait_for(lambda: turning(r), WAIT_S), f"{r} never turned before stop {k + 1}"
            if how == "peer":
                err = peers[target].stop()
            elif how == "console":
                err = console.client(target).send("estop", engaged=True)
            else:
                answered = console.stop_fleet()
                err = None if answered == ROBOTS else f"answered by {answered}"
            for r in targets:
                attempted += 1
                if err is not None:
                    lost.append(f"{robot_now():.1f} s: {how} stop of {r}: {err}")
                elif wait_for(lambda: halted(r), WAIT_S):
                    stopped += 1
                else:
                    lost.append(f"{robot_now():.1f} s: {how} stop of {r}: not engaged with its wheels at zero")
            for r in targets:
                assert console.client(r).send("estop", engaged=False) is None
                assert wait_for(lambda: not console.client(r).view().estop_engaged, WAIT_S)
        while robot_now() < start + SOAK_S:
            time.sleep(0.005)
        assert lost == []
        assert stopped == attempted == 500
    finally:
        for c in peers.values():
            c.close()
        console.close()
        stop.set()
        stepping.join(60)
