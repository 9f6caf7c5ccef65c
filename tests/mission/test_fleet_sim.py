"""Runtimes in lock-step on one simulated greenhouse (``mission.jobs.fleet_sim``): each robot's
commands move it and no other, each runtime's clock is the engine's time when it steps, and a
fleet's run is the same for the same seed."""
from __future__ import annotations

import logging
import math
import time

import pytest

from mission.jobs.fleet_sim import FleetSim, fleet_world, robot_config, start_fleet_sim
from mission.link.telemetry import LOGGING_ROBOT, LinkLogHandler
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from tests.mission.test_log_clock import Posts

WORLD = generate_world(3, 4, 1, robots=2)


def drive_r1(tmp_path, until: float) -> tuple[FleetSim, list[tuple[float, float]], list[tuple[str, str | None]]]:
    """Two robots; r1 is told to drive forward (its own service's teleop, every 0.2 s), r2 is left
    alone; steps the fleet to ``until`` s of runtime time. Returns the fleet and, at every step,
    (the engine's time before it, the time the step was due at), and at every second of each
    runtime (its name, the robot its log records are attributed to)."""
    config = with_overrides(LupinConfig(), {"sim": {"realtime": False}})
    fleet = start_fleet_sim(WORLD, config, ["r1", "r2"], tmp_path, time.perf_counter)
    logged: list[tuple[str, str | None]] = []
    r1 = fleet.services["r1"]
    r1.robot.scheduler.every("test.teleop", 5.0, lambda now: r1.teleop(0.2, 0.0, 0.0))
    for name, service in fleet.services.items():  # whose step it is, as a log record sees it
        service.robot.scheduler.every("test.who", 1.0, lambda now, n=name: logged.append((n, LOGGING_ROBOT.get())))
    steps = []
    while min(s.now for s in fleet.services.values()) < until:
        steps.append((fleet.scene.engine.time, min(s.robot.scheduler.next_due() for s in fleet.services.values())))
        fleet.step()
    return fleet, steps, logged


@pytest.mark.slow
def test_r1s_command_moves_r1_and_not_r2_and_no_runtime_runs_behind_the_engine(tmp_path):
    fleet, steps, logged = drive_r1(tmp_path, 4.0)
    try:
        truth = fleet.scene.truths()
        r1, r2 = (WORLD.spawn_poses[k] for k in (0, 1))
        assert truth["r1"].x - r1.x > 0.3 and abs(truth["r1"].y - r1.y) < 0.05
        assert math.hypot(truth["r2"].x - r2.x, truth["r2"].y - r2.y) < 0.01
        assert fleet.services["r2"].robot.base.odometry.pose.x == pytest.approx(0.0, abs=0.01)
        assert all(engine <= due + 1e-9 for engine, due in steps)  # lock-step: the engine never ahead of a step
        assert fleet.services["r1"].robot.config.link.robot == "r1" and fleet.services["r2"].robot.config.link.robot == "r2"
        assert len(logged) >= 8 and all(task == logging_as for task, logging_as in logged)  # each its own log
        states = [s.robot.estop.latch.directory for s in fleet.services.values()]
        assert all(d.is_dir() for d in states)
    finally:
        fleet.close()
    assert not any(d.exists() for d in states)  # each run's temporary state directory went with it


@pytest.mark.slow
def test_a_fleet_runs_the_same_for_the_same_seed(tmp_path):
    runs = []
    for k in range(2):
        fleet, _, _ = drive_r1(tmp_path / str(k), 3.0)
        try:
            runs.append((fleet.scene.truths(), {n: s.robot.base.odometry.pose for n, s in fleet.services.items()}))
        finally:
            fleet.close()
    assert runs[0] == runs[1]


def test_each_robot_has_its_name_and_its_own_state_directory(tmp_path):
    shared = with_overrides(LupinConfig(), {"runtime": {"state_dir": str(tmp_path)}})
    r2 = robot_config(shared, "r2")
    assert r2.link.robot == "r2" and r2.runtime.state_dir is not None and str(r2.runtime.state_dir) == str(tmp_path / "r2")
    assert robot_config(LupinConfig(), "r3").runtime.state_dir is None  # a fresh temporary one each, as one robot's


def test_the_default_fleet_world_has_a_dock_per_robot():
    assert [len(fleet_world(n).spawn_poses) for n in (1, 2, 3, 5)] == [1, 2, 3, 5]
    assert len(fleet_world(2).pots) == 12  # the built-in greenhouse's 3 rows of 4 pots


def test_a_robots_log_lines_go_to_its_own_link_alone():
    posts = {n: Posts() for n in ("r1", "r2")}
    links = [LinkLogHandler(posts[n], n, lambda: 12.5) for n in posts]
    record = logging.LogRecord("lupin", logging.WARNING, __file__, 1, "SLAM worker lost", None, None)
    token = LOGGING_ROBOT.set("r2")  # r2's step logged it
    try:
        for link in links:
            link.emit(record)
    finally:
        LOGGING_ROBOT.reset(token)
    assert posts["r1"].lines == [] and posts["r2"].lines == ["    12.5 W SLAM worker lost"]
    for link in links:  # logged outside any runtime's step (one robot in the process): every link
        link.emit(record)
    assert len(posts["r1"].lines) == 1 and len(posts["r2"].lines) == 2
