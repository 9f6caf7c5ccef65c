"""One robot's view of an engine that several robots share: its names carry its prefix.

A fleet's greenhouse holds one copy of the robot per robot, each attached under its own name
prefix (``r1/chassis``, ``r2/chassis``: ``sim.greenhouse.build_greenhouse``). The simulated
devices look their parts up by the robot file's names (``chassis``, ``lidar_site``,
``wheel_front_left``); handed a ``Scope`` instead of the engine, they find their own robot's
and nothing else changes in them. Everything else (the model, the data, time, stepping, the
chunk beat) is the shared engine's.

Each robot also draws its own noise: the devices seed their generators from
``engine.config.seed``, so a scope answers a config whose seed is the robot's (``seed``), and
two robots of one run never slip, sag or read their lidar noise in step.
"""
from __future__ import annotations

import mujoco

from sim.config import SimConfig
from sim.engine import Engine


class Scope:
    def __init__(self, engine: Engine, prefix: str, seed: int):
        self.engine, self.prefix = engine, prefix
        self.config: SimConfig = engine.config.model_copy(update={"seed": seed})

    def __getattr__(self, name: str):
        return getattr(self.engine, name)

    def id(self, kind: mujoco.mjtObj, name: str) -> int:
        return self.engine.id(kind, self.prefix + name)

    def joint_qpos(self, name: str) -> int:
        return self.engine.joint_qpos(self.prefix + name)

    def joint_dof(self, name: str) -> int:
        return self.engine.joint_dof(self.prefix + name)

    def actuator(self, name: str) -> int:
        return self.engine.actuator(self.prefix + name)


def robot_seed(seed: int, index: int) -> int:
    """Robot ``index``'s (0-based) noise seed in a run of ``seed``: the first robot's is the run's
    own, so a fleet of one draws what one robot alone does."""
    return seed + 7919 * index
