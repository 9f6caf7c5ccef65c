"""The `lupin sim drive` job: a scripted route through a simulated greenhouse.

Builds the sim backend and the hardware services exactly as a patrol would, drives a route
through the twist_mux (source ``auto``), polls the lidar at 10 Hz like the navigation stack
will, and reports wheel odometry against the sim's ground truth per move.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from hw.errors import InputError
from hw.interfaces import Twist
from hw.odometry import Pose2D
from mission.runtime.config import LupinConfig
from mission.jobs.route import ROUTES, MoveResult, RouteDriver, leaves_the_floor, side_of
from mission.runtime.sim_runtime import SimRuntime, start_sim_runtime
from sim.world import World

LIDAR_RATE = 10.0
ROUTE_TIMEOUT_S = 600.0
HELD_S = 1.0
"""Seconds the collision monitor may hold a move before the route ends: a wall or a pot in the
way does not go away (a spawn 1 m from a wall stopped the tour's strafe, and the command waited
out its whole 600 s); a second is longer than any flicker of a single scan."""


@dataclass
class DriveRun(SimRuntime):
    driver: RouteDriver
    scans: int = 0
    bumps: dict[str, float] = field(default_factory=dict)
    """World geoms the chassis touched, with the first time each was touched (s)."""
    held: str = ""
    """Why the route ended early: the move the collision monitor held, where and how near ('' if not)."""
    _held_since: float | None = None

    @property
    def sim_time(self) -> float:
        return self.robot.scheduler.clock.now()

    @property
    def results(self) -> list[MoveResult]:
        return self.driver.results


def start_drive(world: World, config: LupinConfig, route: str) -> DriveRun:
    """Assemble sim + services + route driver on one scheduler, not yet run. A route that would
    leave the floor from the world's spawn is an ``InputError`` naming the move, before anything moves."""
    s = world.spawn
    problem = leaves_the_floor(ROUTES[route], Pose2D(s.x, s.y, s.yaw), (world.floor.x, world.floor.y),
                               config.nav.costmap.robot_radius)
    if problem:
        raise InputError(f"route {route!r} from {world.name!r}'s spawn: {problem}")
    rt = start_sim_runtime(world, config)
    sim, robot = rt.sim, rt.robot

    def publish(twist: Twist, now: float) -> None:
        robot.mux.publish("auto", twist, now)

    driver = RouteDriver(ROUTES[route], publish, lambda: robot.base.odometry.pose, sim.truth)
    run = DriveRun(sim, robot, rt.state, driver)

    def lidar_tick(now: float) -> None:
        if sim.hal.lidar.latest_scan() is not None:
            run.scans += 1

    def bump_watch(now: float) -> None:
        for name in sim.touching():
            run.bumps.setdefault(name, now)

    def hold_watch(now: float) -> None:
        verdict, move = robot.monitor.verdict, driver.current
        if not verdict.holding or move is None or move.axis == "yaw":
            run._held_since = None
            return
        run._held_since = now if run._held_since is None else run._held_since
        if now - run._held_since >= HELD_S:
            run.held = (f"move {move.name!r} held by the collision monitor ({verdict.action}): something "
                        f"{side_of(move)}, {verdict.nearest:.2f} m from the robot's centre")

    robot.scheduler.every("route", config.hw.base.control_rate, driver.tick)
    robot.scheduler.every("held", config.hw.base.control_rate, hold_watch)
    robot.scheduler.every("lidar", LIDAR_RATE, lidar_tick)
    robot.scheduler.every("bumps", config.hw.base.control_rate, bump_watch)
    return run


def drive(world: World, config: LupinConfig, route: str, timeout: float = ROUTE_TIMEOUT_S) -> DriveRun:
    """Run a route to its end, or until the collision monitor holds a move (``held``), or
    ``timeout`` s of sim time."""
    run = start_drive(world, config, route)
    sched = run.robot.scheduler
    while not run.driver.done and not run.held and sched.clock.now() < timeout:
        sched.step()
    return run
