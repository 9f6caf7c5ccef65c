"""Lighting jitter: seeded, applied to the next frame, reversible."""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from hw.config import HwConfig  # noqa: E402
from sim.backend import SimRobot  # noqa: E402
from sim.config import SimConfig  # noqa: E402
from sim.lighting import LightingJitter  # noqa: E402
from sim.world import load_default_world  # noqa: E402

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def sim():
    s = SimRobot(load_default_world(), SimConfig(), HwConfig())
    s.place(2.0, 0.5, 1.5708)
    yield s
    s.close()


def test_same_seed_same_lighting(sim):
    jitter = LightingJitter(sim.engine.model)
    a = jitter.apply(np.random.default_rng(7))
    diffuse = sim.engine.model.light_diffuse.copy()
    b = jitter.apply(np.random.default_rng(7))
    assert a == b and np.array_equal(sim.engine.model.light_diffuse, diffuse)
    assert 0.65 <= a.brightness <= 1.35 and all(0.92 <= t <= 1.08 for t in a.tint)
    jitter.reset()


def test_brightness_reaches_the_next_frame_and_reset_restores_it(sim):
    jitter = LightingJitter(sim.engine.model)
    cam = sim.hal.cameras["front"]
    base = cam.capture()
    jitter.set(0.65, (1.0, 1.0, 1.0), (0.0, 0.0))
    dim = cam.capture()
    jitter.set(1.35, (1.0, 1.0, 1.0), (0.0, 0.0))
    bright = cam.capture()
    jitter.set(1.0, (1.1, 1.0, 0.9), (0.0, 0.0))
    warm = cam.capture()
    jitter.reset()
    assert dim.mean() < base.mean() < bright.mean()
    assert warm[..., 2].mean() > base[..., 2].mean() and warm[..., 0].mean() < base[..., 0].mean()  # BGR
    assert np.array_equal(cam.capture(), base)
    dirs = sim.engine.model.light_dir
    assert np.allclose(np.linalg.norm(dirs, axis=1), 1.0)

