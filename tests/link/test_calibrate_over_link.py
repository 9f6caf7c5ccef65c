"""The arm's zero-offset calibration end to end from a console on the hw backend (issue 33 item 6):
``lupin serve --backend hw``'s service on the device emulators (the Hiwonder bus on a pty),
its link, and a console's ``arm_calibrate`` start / commit / status / cancel; the runtime's own
beat samples the servos while it commits. The sim refuses it (hardware only)."""
from __future__ import annotations

import threading
import time
from contextlib import ExitStack

import pytest

from hw.config import ServoBusConfig
from mission.jobs.serve import run_service, start_hw_service
from mission.link.client import LinkClient
from mission.link.server import LinkServer, free_endpoint
from mission.runtime.config import LupinConfig
from tests.hw.emulated import emulated_robot
from tests.link.sim_service import TOKEN, client, runtime, wait_for  # noqa: F401  (runtime: the fixture)

pytestmark = pytest.mark.slow
SERVOS = ServoBusConfig()


def zero(joint: str) -> float:
    return SERVOS.joints[joint].home / SERVOS.centideg_per_count


def test_a_console_calibrates_the_arm_on_the_hw_backend(tmp_path):
    with ExitStack() as stack:
        emu = emulated_robot(stack, tmp_path)
        config = LupinConfig.model_validate({"hw": emu.config.model_dump(), "runtime": {"state_dir": str(tmp_path / "state")}})
        service = start_hw_service(config, tmp_path / "runs", time.perf_counter, None, **emu.boundaries())
        endpoint = free_endpoint()
        server = LinkServer(service, config.link, TOKEN, endpoint)
        stop = threading.Event()
        thread = threading.Thread(target=run_service, args=(service, stop, server.close), daemon=True)
        thread.start()
        stack.callback(thread.join, 30)
        stack.callback(stop.set)
        console = LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=TOKEN, timeout=10.0)
        stack.callback(console.close)

        answer, error = console.ask("arm_calibrate", action="start")
        assert error is None and answer["phase"] == "posing" and "pose the arm" in answer["note"]
        bus = emu.servo_bus
        assert wait_for(lambda: not any(bus.servo(SERVOS.joints[j].id).loaded for j in answer["joints"]), 5)
        posed = {"shoulder_lift": 6, "elbow": -4, "wrist": 9, "gripper": -2}  # the operator's hands, counts off zero
        for j, d in posed.items():
            bus.servo(SERVOS.joints[j].id).place(zero(j) + d)
        assert console.ask("arm_calibrate", action="commit")[0]["phase"] == "sampling"
        assert wait_for(lambda: console.ask("arm_calibrate", action="status")[0]["phase"] == "idle", 15)
        done = console.ask("arm_calibrate", action="status")[0]
        assert "4 of 4" in done["note"], done
        for o in done["outcomes"]:
            s = bus.servo(SERVOS.joints[o["joint"]].id)
            assert o["status"] == "written" and abs(o["offset"] - posed[o["joint"]]) <= 1
            assert s.saved_offset == o["offset"] and s.loaded
        assert "start it first" in console.send("arm_calibrate", action="commit")  # refused, said why
        assert console.ask("arm_calibrate", action="start")[0]["phase"] == "posing"
        assert console.ask("arm_calibrate", action="cancel")[0]["phase"] == "idle"
        assert wait_for(lambda: all(bus.servo(SERVOS.joints[j].id).loaded for j in posed), 5)


def test_the_sim_refuses_it_in_one_line(runtime):
    c = client(runtime.endpoint)
    try:
        _, error = c.ask("arm_calibrate", action="start")
        assert "hardware only" in error and "\n" not in error
    finally:
        c.close()
