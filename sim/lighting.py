"""Lighting jitter for perception evaluation: a greenhouse is never lit the same way twice.

The greenhouse model (sim/greenhouse.py) has a fixed headlight, an overhead "sun" and a slanted
"sky" light. :class:`LightingJitter` rescales their intensities (cloud, time of day), tints them
(warm morning, cool overcast) and tilts the sun, all from a seeded generator, by writing the
model's light fields in place; :meth:`LightingJitter.reset` puts the compiled values back.
Renderers read the model on every ``update_scene``, so the next frame sees the new light and
nothing is recompiled. Physics never reads these fields, so a jittered run stays deterministic.
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np


@dataclass(frozen=True)
class Lighting:
    """One draw: what was applied (recorded beside evaluation results)."""

    brightness: float
    """Factor on every light's intensity (1 = as compiled)."""
    tint: tuple[float, float, float]
    """Per-channel RGB factor on top of ``brightness``."""
    sun_tilt: tuple[float, float]
    """Sun direction tilt (x, y) added to the compiled direction before renormalising."""


class LightingJitter:
    def __init__(self, model: mujoco.MjModel, brightness: tuple[float, float] = (0.65, 1.35),
                 tint: float = 0.08, tilt: float = 0.5):
        """``brightness``: range of the intensity factor; ``tint``: largest per-channel
        deviation of the colour factor; ``tilt``: largest sun tilt (0.5 ~ 27 deg)."""
        self.model = model
        self.brightness, self.tint, self.tilt = brightness, tint, tilt
        self._diffuse = model.light_diffuse.copy()
        self._ambient = model.light_ambient.copy()
        self._dir = model.light_dir.copy()
        self._head = (model.vis.headlight.ambient.copy(), model.vis.headlight.diffuse.copy())

    def apply(self, rng: np.random.Generator) -> Lighting:
        """Draw and apply a lighting; the draw depends only on ``rng``'s state."""
        b = float(rng.uniform(*self.brightness))
        tint = 1.0 + rng.uniform(-self.tint, self.tint, 3)
        tilt = rng.uniform(-self.tilt, self.tilt, 2)
        self.set(b, tuple(float(t) for t in tint), (float(tilt[0]), float(tilt[1])))
        return Lighting(b, tuple(float(t) for t in tint), (float(tilt[0]), float(tilt[1])))

    def set(self, brightness: float, tint: tuple[float, float, float], sun_tilt: tuple[float, float]) -> None:
        gain = brightness * np.asarray(tint)
        m = self.model
        m.light_diffuse[:] = self._diffuse * gain
        m.light_ambient[:] = self._ambient * gain
        m.vis.headlight.ambient[:] = self._head[0] * gain
        m.vis.headlight.diffuse[:] = self._head[1] * gain
        d = self._dir.copy()
        d[:, :2] += np.asarray(sun_tilt)
        m.light_dir[:] = d / np.linalg.norm(d, axis=1, keepdims=True)

    def reset(self) -> None:
        """The compiled lighting again."""
        m = self.model
        m.light_diffuse[:] = self._diffuse
        m.light_ambient[:] = self._ambient
        m.light_dir[:] = self._dir
        m.vis.headlight.ambient[:] = self._head[0]
        m.vis.headlight.diffuse[:] = self._head[1]
