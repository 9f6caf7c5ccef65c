"""`lupin serve` on the simulated greenhouse: the service over a real-time MuJoCo runtime.

Kept apart from :mod:`mission.jobs.serve` so that the robot's own service (``--backend hw``)
never imports the simulator.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from hw.odometry import Pose2D
from mission.history.store import History
from mission.jobs.serve import Service
from mission.jobs.sim_patrol import sim_perception
from mission.patrol.climate import TableClimate
from mission.patrol.mission_file import mission_from_world
from mission.patrol.report import pose_error
from mission.runtime.config import LupinConfig
from mission.runtime.navigation import attach_navigation
from mission.runtime.sim_runtime import start_sim_runtime
from nav.frames import compose, inverse
from sim.scene import SimScene
from sim.world import World


def start_sim_service(world: World, config: LupinConfig, runs: Path, wall_now: Callable[[], float],
                      history: History | None = None, scene: SimScene | None = None, name: str = "") -> Service:
    """The service on the simulated greenhouse: the world's climate, truth for judging pots;
    every patrol recorded in ``history`` under the world's name. In a fleet's ``scene``, the
    robot ``name``, with ``world`` as that robot knows it (``World.for_robot``: its own spawn and dock)."""
    rt = start_sim_runtime(world, config, scene, name)
    nav = attach_navigation(rt.robot)
    dock = inverse(Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw))

    def truth_error(goal: Pose2D) -> dict[str, float]:
        return pose_error(compose(dock, rt.sim.truth()), goal)

    return Service(rt.robot, nav, config, sim_perception(config), Path(runs), wall_now, lambda: mission_from_world(world),
                   TableClimate(world.climate_readings()), truth_error, rt.close_backend, history=history, world=world.name)

