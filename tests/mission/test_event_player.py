"""Each scripted action reaches the stack the way the real thing would, on the runtime clock:
one short sim patrol with one event of every kind, checked from outside as it plays."""
from __future__ import annotations

import numpy as np
import pytest

import math

from hw.interfaces import DeviceError
from mission.jobs.sim_patrol import start_sim_patrol
from nav.navigator import State
from mission.patrol.events_file import parse_events
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from sim.world import load_default_world

EVENTS = [
    {"at": 0.0, "do": "controller_race", "controllers": ["mirte_base_controller"], "state": "inactive"},
    {"at": 2.0, "do": "camera_dropout", "camera": "front", "duration": 0.1, "when_moving": 0.1},  # fires on the way to P01
    {"at": 2.0, "do": "battery", "voltage": 9.0, "when_moving": 5.0},  # never: the base never drives that fast
    {"at": 3.5, "do": "teleop", "source": "joy", "vx": 0.0, "vy": 0.0, "wz": 0.5, "duration": 1.0},
    {"at": 5.5, "do": "estop", "engaged": True},
    {"at": 5.5, "do": "soft_estop", "engaged": True},
    {"at": 6.0, "do": "estop", "engaged": False},
    {"at": 6.2, "do": "resume"},
    {"at": 6.5, "do": "soft_estop", "engaged": False},
    {"at": 7.0, "do": "resume"},
    {"at": 9.0, "do": "pause"},
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
        sources, speeds = {}, {}
        while run.elapsed < 5.45:
            run.step()
            sources[round(run.elapsed, 2)] = robot.base.source
            speeds[round(run.elapsed, 2)] = math.hypot(robot.base.odometry.twist.vx, robot.base.odometry.twist.vy)
        assert robot.controllers.is_active("mirte_base_controller")  # healed by the start-up gate
        assert sources[4.0] == "joy" and sources[4.4] == "joy"  # the dead-man holds the wheels
        assert sources[5.0] == "auto" and run.nav.active  # 0.3 s after the stick is let go, autonomy has them

        # when_moving: the first control beat from `at` on at which wheel odometry says 0.1 m/s
        moving = round(run.events.fired[1] - t0, 2)
        assert moving * 10 == pytest.approx(round(moving * 10), abs=1e-6)  # on a control beat
        assert speeds[moving] >= 0.1 and all(v < 0.1 for t, v in speeds.items() if 2.0 <= t < moving)
        assert 2 not in run.events.fired  # 5 m/s never comes: not fired

        sched.run_until(t0 + 5.55)
        assert run.nav.state is State.CANCELED and run.tree.current_step() == "e-stop engaged"  # same instant
        assert robot.base.source == "auto"  # the 5.5 control tick ran before the press ...
        sched.run_until(t0 + 5.65)
        assert robot.base.source == "estop" and not robot.base.last_duties.any()  # ... the next one stops the wheels
        assert robot.leds.state == "estop"  # the strip's 5 Hz beat
        sched.run_until(t0 + 6.3)
        assert run.tree.holds.latched  # the resume at 6.2 was refused: the soft stop still held
        sched.run_until(t0 + 6.9)
        assert "waiting for the operator's resume" in run.tree.current_step() and not run.nav.active
        sched.run_until(t0 + 7.2)
        assert not run.tree.holds.latched and run.nav.active  # resumed: the approach to P01 again

        sched.run_until(t0 + 9.2)
        assert run.tree.holds.paused and run.tree.current_step().startswith("paused")
        assert robot.leds.state == "mission_paused"  # the status strip says the operator must act
        sched.run_until(t0 + 10.6)
        assert not run.tree.holds.paused

        slam = run.nav.localisation
        spawned = slam.spawned
        sched.run_until(t0 + 11.05)
        assert robot.hal.lidar.latest_scan() is None
        with pytest.raises(DeviceError):
            robot.hal.cameras["wrist"].capture()
        assert robot.hal.power.read().voltage == 10.5  # the forced 9.0 never came
        assert slam.occupancy is None and slam.spawned == spawned  # the map is erased, the worker killed
        assert np.allclose(sim.engine.data.mocap_pos[0][:2], (6.0, 0.5))  # the first spare box
        sched.run_until(t0 + 12.5)
        assert slam.spawned == spawned + 1  # a fresh worker, respawn_delay later
        assert robot.hal.lidar.latest_scan() is not None and robot.hal.cameras["wrist"].capture().shape[2] == 3
        assert run.tree.holds.estop_events == [{"t": 5.5, "engaged": True}, {"t": 6.5, "engaged": False}]
        assert sorted(run.events.fired) == [i for i in range(len(EVENTS)) if i != 2]
        assert sorted(e["do"] for e in run.events.applied) == sorted(e["do"] for i, e in enumerate(EVENTS) if i != 2)
        resumes = [e for e in run.events.applied if e["do"] == "resume"]
        assert "still engaged" in resumes[0]["refused"] and "refused" not in resumes[1]
    finally:
        run.close()
