"""Still pictures of the simulated greenhouse, so people can see the world they configured."""
from __future__ import annotations

import numpy as np

from hw.config import HwConfig
from sim.backend import SimRobot
from sim.config import SimConfig
from sim.world import World


def render_snapshot(world: World, sim_config: SimConfig, hw_config: HwConfig, camera: str,
                    pose: tuple[float, float, float] | None = None,
                    arm: dict[str, float] | None = None) -> np.ndarray:
    """BGR image of ``camera`` ('front', 'wrist' or 'overview') with the robot at ``pose``.

    ``arm`` (joint -> radians) places the arm first; the CLI passes ``inspect`` for the wrist
    camera, the pose it is used in on patrol (the sim takes joint angles, not preset names: the
    presets belong to the arm package above it).
    """
    sim = SimRobot(world, sim_config, hw_config)
    try:
        if pose is not None:
            sim.place(*pose)
        if arm is not None:
            sim.servos.place(arm)
        sim.engine.forward()
        if camera == "overview":
            # The orthographic overview frames the floor's y extent; an image of the floor's
            # aspect then shows all of x too (clamped to sane sizes for extreme floors).
            width = sim_config.camera.width
            height = min(max(round(width * world.floor.y / world.floor.x), 240), 2 * width)
            rgb = sim.renderers.render("overview", width, height)
            return np.ascontiguousarray(rgb[:, :, ::-1])
        return sim.hal.cameras[camera].capture()
    finally:
        sim.close()
