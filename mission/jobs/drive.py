"""The `lupin sim drive` job: a scripted route through a simulated greenhouse.

Builds the sim backend and the hardware services exactly as a patrol would, drives a route
through the twist_mux (source ``auto``), polls the lidar at 10 Hz like the navigation stack
will, and reports wheel odometry against the sim's ground truth per move.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from hw.interfaces import Twist
from mission.runtime.config import LupinConfig
from mission.jobs.route import ROUTES, MoveResult, RouteDriver
from mission.runtime.sim_runtime import SimRuntime, start_sim_runtime
from sim.world import World

LIDAR_RATE = 10.0
ROUTE_TIMEOUT_S = 600.0


@dataclass
class DriveRun(SimRuntime):
    driver: RouteDriver
    scans: int = 0
    bumps: dict[str, float] = field(default_factory=dict)
    """World geoms the chassis touched, with the first time each was touched (s)."""

    @property
    def sim_time(self) -> float:
        return self.robot.scheduler.clock.now()

    @property
    def results(self) -> list[MoveResult]:
        return self.driver.results


def start_drive(world: World, config: LupinConfig, route: str) -> DriveRun:
    """Assemble sim + services + route driver on one scheduler, not yet run."""
    rt = start_sim_runtime(world, config)
    sim, robot = rt.sim, rt.robot

    def publish(twist: Twist, now: float) -> None:
        robot.mux.publish("auto", twist, now)

    driver = RouteDriver(ROUTES[route], publish, lambda: robot.base.odometry.pose, sim.truth)
    run = DriveRun(sim, robot, driver)

    def lidar_tick(now: float) -> None:
        if sim.hal.lidar.latest_scan() is not None:
            run.scans += 1

    def bump_watch(now: float) -> None:
        for name in sim.touching():
            run.bumps.setdefault(name, now)

    robot.scheduler.every("route", config.hw.base.control_rate, driver.tick)
    robot.scheduler.every("lidar", LIDAR_RATE, lidar_tick)
    robot.scheduler.every("bumps", config.hw.base.control_rate, bump_watch)
    return run


def drive(world: World, config: LupinConfig, route: str, timeout: float = ROUTE_TIMEOUT_S) -> DriveRun:
    """Run a route to its end (or ``timeout`` s of sim time)."""
    run = start_drive(world, config, route)
    sched = run.robot.scheduler
    while not run.driver.done and sched.clock.now() < timeout:
        sched.step()
    return run
