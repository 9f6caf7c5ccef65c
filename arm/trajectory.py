"""A joint trajectory: all four arm joints from where they are to a goal, together.

Seed: Lupin commands the four arm joints "together as a single trajectory" in joint order
(joint_trajectory_controller). The controller samples it at its 10 Hz beat and hands each
sample to the dead-band write loop, which sends a joint only when its sample moved past
SERVO_COMMAND_DIFF, so a slow joint in a long move is written less often than a fast one.
Linear in joint space: every joint starts and ends together, and the duration follows from
the longest way to go at the maximum joint speed (``arm.presets.move_duration``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Trajectory:
    start: np.ndarray
    goal: np.ndarray
    t0: float
    duration: float
    label: str = ""

    def sample(self, t: float) -> np.ndarray:
        """The commanded joint angles at runtime ``t`` (held at the goal once done)."""
        s = 1.0 if self.duration <= 0 else min(max((t - self.t0) / self.duration, 0.0), 1.0)
        return self.start + (self.goal - self.start) * s

    def done(self, t: float) -> bool:
        return t >= self.t0 + self.duration
