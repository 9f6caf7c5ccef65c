"""Sim test builders: an open-floor world and a robot assembled on the MuJoCo backend."""
from __future__ import annotations

import pytest

from mission.config import load_config
from mission.robot import build_robot
from sim.backend import SimRobot
from sim.world import Floor, Pose2, World


def open_floor(spawn=(3.0, 3.0, 0.0), size=(8.0, 6.0)) -> World:
    """An empty greenhouse: nothing to bump into, so truth is what the wheels achieved."""
    return World(name="open", floor=Floor(x=size[0], y=size[1]), spawn=Pose2(x=spawn[0], y=spawn[1], yaw=spawn[2]), pots=[])


def assemble(world: World, seed: int = 0, **env):
    config = load_config(env={"LUPIN_SIM__SEED": str(seed), **env})
    sim = SimRobot(world, config)
    robot = build_robot(config, sim.hal)
    sim.faults.controllers = robot.controllers
    robot.start()
    return sim, robot


@pytest.fixture
def config():
    return load_config(env={})
