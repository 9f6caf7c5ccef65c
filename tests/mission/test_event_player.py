"""Each scripted action reaches the stack the way the real thing would, on the runtime clock:
one short sim patrol with one event of every kind, checked from outside as it plays."""
from __future__ import annotations

import numpy as np
import pytest

from hw.interfaces import DeviceError
from mission.jobs.patrol import start_sim_patrol
from mission.patrol.events_file import parse_events
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from sim.world import load_default_world

EVENTS = [
    {"at": 0.0, "do": "controller_race", "controllers": ["mirte_base_controller"], "state": "inactive"},
    {"at": 6.0, "do": "teleop", "source": "joy", "vx": 0.0, "vy": 0.0, "wz": 0.5, "duration": 1.0},
    {"at": 9.0, "do": "pause"},
    {"at": 9.5, "do": "estop", "engaged": True},
    {"at": 9.5, "do": "soft_estop", "engaged": True},
    {"at": 10.0, "do": "estop", "engaged": False},
    {"at": 10.0, "do": "soft_estop", "engaged": False},
    {"at": 10.5, "do": "resume"},
    {"at": 11.0, "do": "lidar_dropout", "duration": 1.0},
    {"at": 11.0, "do": "camera_dropout", "camera": "wrist", "duration": 1.0},
    {"at": 11.0, "do": "battery", "voltage": 10.5},
    {"at": 11.0, "do": "clear_map"},
    {"at": 11.0, "do": "place_box", "x": 6.0, "y": 0.5, "sx": 0.2, "sy": 0.4},
    {"at": 11.0, "do": "servo_stall", "joint": "elbow", "mode": "latch"},
]


@pytest.mark.slow
def test_every_action_reaches_the_stack_at_its_time(tmp_path):
    config = LupinConfig()
    world = load_default_world()
    events = parse_events(EVENTS, "events", config)
    run = start_sim_patrol(world, mission_from_world(world), config, tmp_path / "report.json", lambda: 0.0, events)
    robot, sim, sched = run.robot, run.sim.sim, run.robot.scheduler
    t0 = run.report.t0
    try:
        sources = {}
        while run.elapsed < 8.0:
            run.step()
            sources[round(run.elapsed, 2)] = robot.base.source
        assert robot.controllers.is_active("mirte_base_controller")  # healed by the start-up gate
        assert sources[6.5] == "joy" and sources[6.9] == "joy"  # the dead-man holds the wheels
        assert sources[7.5] != "joy"  # 0.3 s after the stick is let go, it no longer does

        sched.run_until(t0 + 9.2)
        assert run.tree.holds.paused and run.tree.current_step().startswith("paused")
        assert not run.nav.active  # the pause stopped the approach: goal cancelled
        sched.run_until(t0 + 9.6)
        assert robot.estop.engaged() and robot.base.source == "estop"
        sched.run_until(t0 + 10.2)
        assert not robot.estop.engaged() and "waiting for the operator's resume" in run.tree.current_step()
        sched.run_until(t0 + 10.6)
        assert not run.tree.holds.latched and not run.tree.holds.paused

        slam = run.nav.localisation
        spawned = slam.spawned
        sched.run_until(t0 + 11.05)
        assert robot.hal.lidar.latest_scan() is None
        with pytest.raises(DeviceError):
            robot.hal.cameras["wrist"].capture()
        assert robot.hal.power.read().voltage == 10.5
        assert slam.occupancy is None and slam.spawned == spawned  # the map is erased, the worker killed
        assert np.allclose(sim.engine.data.mocap_pos[0][:2], (6.0, 0.5))  # the first spare box
        sched.run_until(t0 + 12.5)
        assert slam.spawned == spawned + 1  # a fresh worker, respawn_delay later
        assert robot.hal.lidar.latest_scan() is not None and robot.hal.cameras["wrist"].capture().shape[2] == 3
        assert run.tree.holds.estop_events == [{"t": 9.5, "engaged": True}, {"t": 10.0, "engaged": False}]
        assert [e["do"] for e in run.events.applied] == [e["do"] for e in EVENTS]
    finally:
        run.close()
