"""Robot assembly: the hardware services wired onto a HAL and put on the scheduler.

Reads like a table of contents of what runs below the mission, and at what beat:

====================  =========  ==============================================
task                  rate       why (seed)
====================  =========  ==============================================
base                  10 Hz      controller_manager update_rate: 10
estop                 5 Hz       estop_bridge publishes /e_stop_state at 5 Hz
leds                  5 Hz       status strip follows drive / e-stop activity
arm                   10 Hz      arm HW interface write loop (dead-band re-assert) at 10 Hz
power                 2 Hz       power_watcher: percentage, power-low after 20 s below 11.1 V
monitor               10 Hz      the collision monitor's scan trust (blind, stale) at the base's beat
monitor.off           1/min      on the robot only: a monitor turned off is an ERROR every minute
====================  =========  ==============================================

Every velocity source publishes into ``mux``; the base controller reads only the mux, through
the collision monitor (the raw scan, every source), and checks the e-stop bridge itself on
every tick, so the wheels stop on the very next tick after a press even if everything above
hangs.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from arm.controller import ArmController
from arm.outline import arm_capsules
from hw.base_controller import BaseController
from hw.collision_monitor import CollisionMonitor
from hw.controller_manager import ControllerManager
from hw.errors import InputError
from hw.estop import EStopBridge
from hw.soft_stop_latch import SoftStopLatch
from hw.interfaces import Hal
from hw.leds import LedStatus, pick_state
from hw.robot_outline import NO_CAPSULES, Capsules
from hw.power_policy import RATE as POWER_RATE
from hw.power_policy import PowerWatch
from hw.twist_mux import TwistMux
from mission.runtime.config import LupinConfig
from mission.runtime.scheduler import Scheduler

if TYPE_CHECKING:
    from mission.runtime.people import People

log = logging.getLogger("lupin")

LED_RATE = 5.0
MONITOR_RATE = 10.0
"""The monitor judges its scans' trust at the base's beat even while nothing asks it for a twist
(e-stopped, idle), so ``untrusted_since`` and the blind fault stay current."""
MONITOR_OFF_RATE = 1.0 / 60.0
"""On the robot, a collision monitor turned off is logged again every minute (runtime clock)."""


@dataclass
class Robot:
    config: LupinConfig
    hal: Hal
    scheduler: Scheduler
    controllers: ControllerManager
    mux: TwistMux
    estop: EStopBridge
    base: BaseController
    leds: LedStatus
    arm: ArmController
    power: PowerWatch
    monitor: CollisionMonitor
    on_robot: bool = False
    """The hw backend (the real devices), not the sim."""
    closers: list[Callable[[], None]] = field(default_factory=list)
    """What ``close`` shuts down (worker processes, devices), in order."""
    mission_state: Callable[[], str | None] = lambda: None
    """The mission's state for the status strip ('running', 'paused', 'done', 'failed' or None:
    no mission); a patrol sets it, the robot only reads it."""
    people: "People | None" = None
    """The person tracker's runtime (``mission.runtime.people``), once navigation is attached."""

    def close(self) -> None:
        for close in self.closers:
            close()
        self.closers.clear()

    def restart(self, now: float) -> None:
        """The runtime as its service starts it again after a crash (the ``runtime_crash``
        event): what it held in memory is dropped (every twist on the mux, the wheel PID, the soft
        stop) and what it persisted (the soft stop's latch) is read again."""
        self.estop.restart()
        self.mux.discard_until(now)
        self.base.pid.reset()

    def _led_tick(self, now: float) -> None:
        c = self.base.command
        self.leds.show(pick_state(estop=self.estop.engaged(), battery_low=self.power.state.low,
                                  mission=self.mission_state(), driving=max(abs(c.vx), abs(c.vy), abs(c.wz)) > 1e-3))

    def start(self) -> None:
        hw = self.config.hw
        self.scheduler.every("base", hw.base.control_rate, self.base.tick)
        self.scheduler.every("estop", hw.estop.publish_rate, self.estop.publish)
        self.scheduler.every("leds", LED_RATE, self._led_tick)
        self.scheduler.every("arm", self.config.arm.reassert.rate, self.arm.tick)
        self.scheduler.every("power", POWER_RATE, self.power.tick)
        self.scheduler.every("monitor", MONITOR_RATE, self.monitor.check)
        if not hw.collision_monitor.enabled:
            if self.on_robot:
                self.scheduler.every("monitor.off", MONITOR_OFF_RATE, _monitor_off)
            else:
                log.warning("collision monitor off (hw.collision_monitor.enabled: false): nothing checks the "
                            "twist against the lidar")


def _monitor_off(now: float) -> None:
    log.error("COLLISION MONITOR OFF (--no-collision-monitor): the base drives into whatever it is told to")


def check_monitor_switch(config: LupinConfig, on_robot: bool, monitor_off: bool) -> LupinConfig:
    """The config the robot runs, with the ``--no-collision-monitor`` option applied: on the robot
    the monitor is turned off only by that option, never silently by a config file (issue 28
    item 6); in the sim ``enabled: false`` is allowed (bump tests need it) and warned about."""
    cm = config.hw.collision_monitor
    if monitor_off:
        return config.model_copy(update={"hw": config.hw.model_copy(update={
            "collision_monitor": cm.model_copy(update={"enabled": False})})})
    if on_robot and not cm.enabled:
        raise InputError("hw.collision_monitor.enabled is false in the config: on the robot the collision monitor "
                         "is turned off only with --no-collision-monitor (lupin serve --backend hw --no-collision-monitor)")
    return config


def arm_outline(arm: ArmController, config: LupinConfig) -> Callable[[], Capsules]:
    """The arm's capsules as it stands, for the collision monitor (hw never imports arm)."""
    def outline() -> Capsules:
        q = arm.joint_vector()
        return NO_CAPSULES if q is None else arm_capsules(q, config.arm.kinematics)

    return outline


def build_robot(config: LupinConfig, hal: Hal, controllers: ControllerManager | None = None,
                state: Path | None = None, on_robot: bool = False, monitor_off: bool = False) -> Robot:
    """Assemble the hardware services on ``hal``; call ``start()`` to schedule them. ``state``:
    the runtime's state directory (the soft stop's latch lives there); None keeps it in memory.
    ``on_robot``: the hw backend; ``monitor_off``: the command's ``--no-collision-monitor``."""
    config = check_monitor_switch(config, on_robot, monitor_off)
    hw = config.hw
    controllers = controllers or ControllerManager(hw.controllers)
    mux = TwistMux(hw.mux)
    estop = EStopBridge(hw.estop, hal.estop_button, log, None if state is None else SoftStopLatch(state, log))
    arm = ArmController(config.arm, hw.servos, hal.servos, controllers, log)
    monitor = CollisionMonitor(hw.collision_monitor, hal.lidar, config.nav.costmap.robot_radius,
                               config.nav.navigator.lidar_mount, log, arm=arm_outline(arm, config))
    base = BaseController(hw.base, hal.wheels, hal.encoders, mux, estop, controllers, guard=monitor)
    leds = LedStatus(hw.leds, hal.leds)
    power = PowerWatch(hw.devices.power, hal.power, log)
    robot = Robot(config, hal, Scheduler(hal.clock), controllers, mux, estop, base, leds, arm, power, monitor,
                  on_robot=on_robot)
    robot.closers.append(estop.close)
    return robot
