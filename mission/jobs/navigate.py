"""The `lupin sim navigate` job: one goal through the whole navigation stack in the sim.

The sim runtime (MuJoCo + the hardware services) with navigation attached; the goal is given in
the world frame, as ``sim snapshot --pose`` takes it, and handed to the navigator in the map
frame, whose origin is the robot's start pose (spec/mission.md). Truth is recorded beside
odometry for judging only: the navigator never sees it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

from hw.odometry import Pose2D
from mission.jobs.contacts import ContactLog
from mission.runtime.config import LupinConfig
from mission.runtime.navigation import attach_navigation, final_map
from mission.runtime.sim_runtime import SimRuntime, start_sim_runtime
from nav.frames import compose, inverse, yaw_error
from nav.navigator import Navigator
from nav.occupancy import OccupancyMap
from sim.world import World

TRACE_RATE = 10.0
#: Extra sim time past the goal's own timeout before the job gives up on the navigator itself.
GRACE_S = 5.0


@dataclass
class NavigateRun(SimRuntime):
    nav: Navigator
    spawn: Pose2D
    truth_path: list[Pose2D] = field(default_factory=list)
    """Ground truth in the world frame, at 10 Hz (judging only)."""
    odom_path: list[Pose2D] = field(default_factory=list)
    """The robot's own belief, its map pose (SLAM's map -> odom on wheel odometry), carried
    into the world frame, at 10 Hz."""
    bumps: dict[str, float] = field(default_factory=dict)
    """World geoms the chassis touched, with the first time each was touched (s)."""
    contacts: ContactLog | None = None
    """Every contact onset (a body touching the chassis again counts again), sampled every
    physics chunk; what a trial counts bumps from."""
    plans: list = field(default_factory=list)
    """Every distinct global plan the navigator made (map frame), oldest first."""

    @property
    def now(self) -> float:
        return self.robot.scheduler.clock.now()

    def to_map(self, world_pose: Pose2D) -> Pose2D:
        return compose(inverse(self.spawn), world_pose)

    def go(self, goal_world: Pose2D, timeout: float | None = None,
           progress: Callable[["NavigateRun"], None] | None = None) -> str:
        """Navigate to a world-frame goal and run the scheduler until the goal ends; returns
        the outcome (succeeded / failed / canceled)."""
        timeout = timeout if timeout is not None else self.robot.config.nav.navigator.default_timeout
        self.wait_ready()
        self.nav.navigate_to(self.to_map(goal_world), self.now, timeout)
        end = self.now + timeout + GRACE_S
        next_progress = self.now
        sched = self.robot.scheduler
        while self.nav.active and self.now < end:
            sched.step()
            if progress is not None and self.now >= next_progress:
                progress(self)
                next_progress = self.now + 1.0
        if self.nav.active:  # the navigator's own timeout must have fired; never hang regardless
            self.nav.cancel(self.now, "job timeout")
        return self.nav.state.value

    def wait_ready(self) -> bool:
        """Run until the readiness cascade is active, or its ceiling passes (the goal then fails
        with the missing stage as its reason)."""
        readiness, sched = self.nav.readiness, self.robot.scheduler
        while not readiness.tick(self.now) and not readiness.overdue(self.now):
            sched.step()
        return readiness.active

    def truth_error(self, goal_world: Pose2D) -> tuple[float, float]:
        t = self.sim.truth()
        return math.hypot(t.x - goal_world.x, t.y - goal_world.y), yaw_error(t, goal_world)

    def final_map(self) -> OccupancyMap | None:
        return final_map(self.nav, self.robot.scheduler)

    @property
    def distance(self) -> float:
        return self.robot.base.odometry.distance


def start_navigate(world: World, config: LupinConfig) -> NavigateRun:
    """Sim + services + navigation on one scheduler, tracing truth and odometry; not yet run."""
    rt = start_sim_runtime(world, config)
    sim, robot = rt.sim, rt.robot
    spawn = Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw)
    run = NavigateRun(sim, robot, rt.state, attach_navigation(robot), spawn)
    run.contacts = ContactLog(sim.touching)
    sim.engine.attach(run.contacts)

    def trace(now: float) -> None:
        run.truth_path.append(sim.truth())
        run.odom_path.append(compose(spawn, run.nav.map_pose()))
        for name in sim.touching():
            run.bumps.setdefault(name, now)
        if run.nav.path is not None and (not run.plans or run.plans[-1] is not run.nav.path):
            run.plans.append(run.nav.path)

    robot.scheduler.every("trace", TRACE_RATE, trace)
    return run
