"""Rendered frames for the perception tests: one small greenhouse, rendered once per session.

Each pot is shot from its exact approach pose (spec/mission.md): the wrist camera with the arm
at ``inspect`` and the front camera. Ground truth comes from the sim (segmentation pixels,
the tag's true pose in the camera), through the evaluation harness's own functions.
"""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

from dataclasses import dataclass  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from arm.presets import preset  # noqa: E402
from lupin.bench.perception import approach_pose, flower_truth_of, tag_truth  # noqa: E402
from mission.runtime.config import LupinConfig  # noqa: E402
from sim.backend import SimRobot  # noqa: E402
from sim.generate import generate_world  # noqa: E402
from sim.lighting import LightingJitter  # noqa: E402

# id -> (flower, blooms, bug, tag); laid over a generated 2 x 4 greenhouse.
POTS = {
    "P01": ("red", 1, False, 0),
    "P02": ("white", 1, False, 1),
    "P03": ("pink", 1, False, 2),
    "P04": ("none", 1, False, 3),
    "P05": ("red", 2, False, 4),
    "P06": ("pink", 2, True, 21),
    "P07": ("white", 3, False, 6),
    "P08": ("red", 1, True, 7),
}


@dataclass(frozen=True)
class Scene:
    wrist: np.ndarray
    front: np.ndarray
    flower_truth: object
    count_truth: object
    bug_truth: object
    tag: int
    tag_rotation: np.ndarray
    tag_position: np.ndarray
    tag_in_view: bool


def build_world():
    world = generate_world(2, 4, seed=5)
    pots = [p.model_copy(update=dict(zip(("flower", "blooms", "bug", "tag"), POTS[p.id]))) for p in world.pots]
    return world.model_copy(update={"pots": pots, "climate": {}})


class Studio:
    """A sim greenhouse with the arm at ``inspect`` that shoots pots on demand."""

    def __init__(self, config: LupinConfig):
        self.config = config
        self.world = build_world()
        self.sim = SimRobot(self.world, config.sim, config.hw)
        self.sim.servos.place(preset("inspect"))
        self.seg = mujoco.Renderer(self.sim.engine.model, config.sim.camera.height, config.sim.camera.width)
        self.seg.enable_segmentation_rendering()
        self.lights = LightingJitter(self.sim.engine.model)

    def pot(self, pot_id: str):
        return next(p for p in self.world.pots if p.id == pot_id)

    def shoot(self, pot_id: str, noise=(0.0, 0.0, 0.0), lighting=None) -> Scene:
        pot = self.pot(pot_id)
        self.sim.place(*approach_pose(pot, noise))
        if lighting is None:
            self.lights.reset()
        else:
            self.lights.set(*lighting)
        cams = self.sim.hal.cameras
        wrist, front = cams["wrist"].capture(), cams["front"].capture()
        flower, count, bug = flower_truth_of(self.sim, self.seg, pot)
        rot, pos, in_view = tag_truth(self.sim, pot, self.config)
        return Scene(wrist, front, flower, count, bug, pot.tag, rot, pos, in_view)

    def close(self) -> None:
        self.seg.close()
        self.sim.close()


@pytest.fixture(scope="session")
def studio():
    s = Studio(LupinConfig())
    yield s
    s.close()


@pytest.fixture(scope="session")
def scenes(studio) -> dict[str, Scene]:
    """Every pot from its exact approach pose under the compiled lighting."""
    return {pot_id: studio.shoot(pot_id) for pot_id in POTS}
