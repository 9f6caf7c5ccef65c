"""A runtime on the simulated robot: the MuJoCo backend plus the hardware services, wired.

The one place that joins the two: the services get the sim's HAL (and its clock), and the
sim's fault hooks get the runtime's controller manager, so a scripted "controller comes up
broken" reaches the same manager the base controller consults. Everything that runs on the
sim (the drive and navigate jobs, the patrol, the service, scenarios) starts here.
"""
from __future__ import annotations

from dataclasses import dataclass

from hw.controller_manager import ControllerManager
from mission.runtime.config import LupinConfig
from mission.runtime.robot import Robot, build_robot
from sim.backend import SimRobot
from sim.world import World


@dataclass
class SimRuntime:
    sim: SimRobot
    robot: Robot

    def close(self) -> None:
        self.robot.close()
        self.sim.close()


def start_sim_runtime(world: World, config: LupinConfig) -> SimRuntime:
    """Build the sim and the services on it and schedule them (nothing has run yet)."""
    controllers = ControllerManager(config.hw.controllers)
    sim = SimRobot(world, config.sim, config.hw, controllers)
    robot = build_robot(config, sim.hal, controllers)
    robot.start()
    return SimRuntime(sim, robot)
