"""A runtime on the simulated robot: the MuJoCo backend plus the hardware services, wired.

The one place that joins the two: the services get the sim's HAL (and its clock), and the
sim's fault hooks get the runtime's controller manager, so a scripted "controller comes up
broken" reaches the same manager the base controller consults. Everything that runs on the
sim (the drive and navigate jobs, the patrol, the service, scenarios) starts here.
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

from hw.controller_manager import ControllerManager
from mission.runtime.config import LupinConfig
from mission.runtime.robot import Robot, build_robot
from mission.runtime.state_dir import state_directory
from sim.backend import SimRobot
from sim.scene import SimScene
from sim.world import World


@dataclass
class SimRuntime:
    sim: SimRobot
    robot: Robot
    state: Path
    """The runtime's state directory: ``runtime.state_dir``, or this run's own temporary one."""

    def close(self) -> None:
        self.robot.close()
        self.close_backend()

    def close_backend(self) -> None:
        """The sim, and this run's temporary state directory with it (a service closes its robot
        first, then this: a sim run leaves nothing behind in the temporary directory)."""
        self.sim.close()
        if self.robot.config.runtime.state_dir is None:
            shutil.rmtree(self.state, ignore_errors=True)


def start_sim_runtime(world: World, config: LupinConfig, scene: SimScene | None = None, name: str = "") -> SimRuntime:
    """Build the sim and the services on it and schedule them (nothing has run yet). ``scene``:
    a fleet's greenhouse to put the robot ``name`` in (``sim.scene``); None: one of its own."""
    controllers = ControllerManager(config.hw.controllers)
    sim = SimRobot(world, config.sim, config.hw, controllers, scene=scene, name=name)
    state = state_directory(config.runtime, "sim")
    robot = build_robot(config, sim.hal, controllers, state)
    robot.start()
    return SimRuntime(sim, robot, state)
