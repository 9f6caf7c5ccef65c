"""The console's bindings against a real sim runtime over the link: each key under Pilot, and
what the robot did about it (read from the runtime itself)."""
from __future__ import annotations

import asyncio
import time

import numpy as np
import pytest

from arm.limits import GRIPPER_CLOSED_DEG, GRIPPER_OPEN_DEG, clamp_arm, gripper_deg_to_rad
from arm.presets import PRESETS, preset
from mission.link.client import LinkClient
from tests.link.sim_service import TOKEN, runtime  # noqa: F401  (runtime: the fixture)
from tui.keys import ARM_PRESETS
from tui.app import make_app

pytestmark = pytest.mark.slow


def press(endpoint, keys, then=lambda: True, timeout=10.0):
    """Press ``keys`` in a console attached to the runtime, once its view is connected; then
    wait (in the app) until ``then()``."""
    client = LinkClient(endpoint, "mirte", clock=time.monotonic, token=TOKEN, timeout=10.0)

    async def go():
        app = make_app(client.view, client)
        async with app.run_test(size=(160, 48)) as pilot:
            end = time.monotonic() + 10
            while not client.view().connected and time.monotonic() < end:
                await pilot.pause(0.05)
            for k in keys:
                await pilot.press(k)
            await app.workers.wait_for_complete()
            end = time.monotonic() + timeout
            while not then() and time.monotonic() < end:
                await pilot.pause(0.05)
            return then()

    try:
        return asyncio.run(go())
    finally:
        client.close()


def test_every_binding_moves_the_sim_robot(runtime):
    service, endpoint = runtime.service, runtime.endpoint
    robot = service.robot

    def manual():  # what the runtime took on the console's teleop source
        last = robot.mux.last("manual")
        return last[1] if last is not None else None

    assert press(endpoint, ["left"] * 3, lambda: manual() is not None and manual().vy > 0)
    assert press(endpoint, ["q"] * 3, lambda: manual().wz > 0 and manual().vy == 0)
    assert press(endpoint, ["space"], lambda: robot.estop.engaged() and robot.base.source == "estop")
    assert press(endpoint, ["u"], lambda: not robot.estop.engaged())
    assert press(endpoint, ["m"], lambda: service.run is not None and service.run.tree.current_step() != "")
    assert press(endpoint, ["p"], lambda: service.run.tree.holds.paused)
    assert press(endpoint, ["r"], lambda: not service.run.tree.holds.paused)
    assert press(endpoint, ["space", "space", "u"],
                 lambda: service.run.tree.holds.latched and not robot.estop.engaged())  # released, the mission still held
    assert press(endpoint, ["r"], lambda: not service.run.tree.holds.latched)
    slam = service.nav.localisation
    spawned = slam.spawned
    assert press(endpoint, ["c", "n"]) and slam.spawned == spawned  # asked, declined
    assert press(endpoint, ["c", "y"], lambda: slam.spawned == spawned + 1, timeout=5)  # the map reset: SLAM respawned
    # arm and gripper: the patrol must not be moving the arm, so abort it first (through the link)
    client = LinkClient(endpoint, "mirte", clock=time.monotonic, token=TOKEN, timeout=10.0)
    try:
        assert client.send("mission_abort") is None
    finally:
        client.close()

    def arm_going_to(name):  # on its way there (the whole move is the arm's tests' business), or there
        def check():
            tr = robot.arm.trajectory
            return (tr is not None and np.allclose(tr.goal, clamp_arm(PRESETS[name]), atol=1e-6)) \
                or robot.arm.at(preset(name), tol=0.05)
        return check

    for i, name in enumerate(ARM_PRESETS):
        assert press(endpoint, [str(i + 1)], arm_going_to(name)), name
    assert press(endpoint, ["o"], lambda: robot.arm.gripper.goal == gripper_deg_to_rad(GRIPPER_OPEN_DEG))
    assert press(endpoint, ["g"], lambda: robot.arm.gripper.goal == gripper_deg_to_rad(GRIPPER_CLOSED_DEG))
