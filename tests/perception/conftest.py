"""Rendered frames for the perception tests: one small greenhouse, rendered once per session.

Each pot is shot from its exact approach pose (spec/mission.md): the wrist camera with the arm
at the patrol's inspect view (``patrol.inspect_pose``) and the front camera. The sim puts every
pest of this greenhouse on a leaf unless the pot's entry says ``bloom`` (``leaf_pest_share``
1 or 0: ``LEAF`` / the rest), so leaf pests are shot on flowering plants and on a plant with
no bloom. Ground truth comes from the sim (segmentation pixels,
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
from mission.patrol.config import PatrolConfig  # noqa: E402
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
LEAF = {
    "P09": ("none", 1, True, 8),
    "P10": ("white", 3, True, 9),
    "P11": ("red", 2, True, 10),
}
"""Pots whose pest the sim draws on a leaf (shot in a greenhouse of their own)."""


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


def build_world(pots: dict = POTS):
    world = generate_world(2, 4, seed=5)
    placed = [p.model_copy(update={"id": pid, **dict(zip(("flower", "blooms", "bug", "tag"), plant))})
              for p, (pid, plant) in zip(world.pots, pots.items())]
    return world.model_copy(update={"pots": placed, "climate": {}})


class Studio:
    """A sim greenhouse with the arm at the patrol's inspect view that shoots pots on demand."""

    def __init__(self, config: LupinConfig, pots: dict = POTS):
        self.config = config
        self.world = build_world(pots)
        self.sim = SimRobot(self.world, config.sim, config.hw)
        self.sim.servos.place(preset(PatrolConfig().inspect_pose))
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


def _with_leaf_share(share: float) -> LupinConfig:
    c = LupinConfig()
    geometry = c.sim.geometry.model_copy(update={"leaf_pest_share": share})
    return c.model_copy(update={"sim": c.sim.model_copy(update={"geometry": geometry})})


@pytest.fixture(scope="session")
def studio():
    s = Studio(_with_leaf_share(0.0))  # every flowering plant's pest on its bloom
    yield s
    s.close()


@pytest.fixture(scope="session")
def leaf_scenes() -> dict[str, Scene]:
    """The ``LEAF`` pots, every pest on a leaf, from the exact approach pose."""
    s = Studio(_with_leaf_share(1.0), LEAF)
    try:
        yield {pot_id: s.shoot(pot_id) for pot_id in LEAF}
    finally:
        s.close()


@pytest.fixture(scope="session")
def scenes(studio) -> dict[str, Scene]:
    """Every pot from its exact approach pose under the compiled lighting."""
    return {pot_id: studio.shoot(pot_id) for pot_id in POTS}
