"""A runtime on the real robot: its devices behind the HAL, the services and navigation on them.

The hardware twin of ``mission.runtime.sim_runtime``: every device is opened first (a missing
one is one ``InputError`` naming it, before anything moves), then the services are scheduled
and navigation attached. Between the two, the loop's compiled kernels are compiled
(``mission.runtime.warm_up``: 40 s on the first start after an install; after the devices,
so a missing one is said at once). ``close`` shuts the services down, then releases the devices.
"""
from __future__ import annotations

from dataclasses import dataclass

from hw.backend import HwBackend
from mission.runtime.config import LupinConfig
from mission.runtime.navigation import attach_navigation
from mission.runtime.robot import Robot, build_robot, check_monitor_switch
from mission.runtime.state_dir import state_directory
from mission.runtime.warm_up import warm_up
from nav.navigator import Navigator


@dataclass
class HwRuntime:
    backend: HwBackend
    robot: Robot
    nav: Navigator

    def close(self) -> None:
        self.robot.close()
        self.backend.close()


def start_hw_runtime(config: LupinConfig, monitor_off: bool = False, **boundaries) -> HwRuntime:
    """``monitor_off``: the command's ``--no-collision-monitor`` (the only way to run the robot
    without the collision monitor; a config that turns it off is refused before a device opens).
    ``boundaries``: ``HwBackend``'s I2C bus and GPIO requests (the device emulators, in tests)."""
    check_monitor_switch(config, True, monitor_off)
    state = state_directory(config.runtime, "hw")  # before any device opens: no latch, no start
    backend = HwBackend(config.hw, **boundaries)
    try:
        warm_up(config)  # nothing scheduled yet: the loop never stops to compile (mission.runtime.warm_up)
        robot = build_robot(config, backend.hal, state=state, on_robot=True, monitor_off=monitor_off)
        robot.start()
        return HwRuntime(backend, robot, attach_navigation(robot))
    except BaseException:
        backend.close()
        raise
