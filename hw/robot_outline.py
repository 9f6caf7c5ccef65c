"""The robot's outline on the floor plane: the chassis rectangle plus capsules (the arm as it
stands), in the base frame.

The collision monitor needs the body it protects twice: to drop the lidar's returns off the
robot itself (a return inside the outline is the robot), and to carry that body along a twist
to see what it would touch. A circle of the navigation radius (0.22 m) does neither well: the
chassis is 0.33 x 0.26 m (sim/models/mirte_master/README.md, the ``chassis`` geom), so a circle
hides a leg 5-9 cm off its side, and a circle turning on the spot sweeps nothing new while a
rectangle's corners and an outstretched arm do (issue 28 item 6).

The arm's part comes from above as data (``Capsules``: segments and a radius, from the joint
states; ``arm.outline`` builds them): hw never imports arm.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Capsules:
    """Line segments thickened by ``radius``: links seen from above."""

    segments: np.ndarray
    """(M, 2, 2): each segment's two ends (x, y), base frame, m."""
    radius: float
    """Half the links' width, m."""


NO_CAPSULES = Capsules(np.zeros((0, 2, 2)), 0.0)


class Outline:
    """The chassis box (centred on the base frame) plus capsules."""

    def __init__(self, half_length: float, half_width: float, capsules: Capsules = NO_CAPSULES):
        self.half_length, self.half_width, self.capsules = half_length, half_width, capsules
        ends = capsules.segments.reshape(-1, 2)
        arm = float(np.hypot(ends[:, 0], ends[:, 1]).max()) + capsules.radius if len(ends) else 0.0
        self.reach = max(float(np.hypot(half_length, half_width)), arm)
        """The farthest any part of the outline is from the base centre, m."""

    def inside(self, x: np.ndarray, y: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Which points (x, y: arrays of one shape, base frame) lie within ``margin`` of the
        outline. Vectorised over the points; a loop only over the few capsules."""
        hit = (np.abs(x) < self.half_length + margin) & (np.abs(y) < self.half_width + margin)
        r2 = (self.capsules.radius + margin) ** 2
        for (ax, ay), (bx, by) in self.capsules.segments:
            dx, dy = bx - ax, by - ay
            n = dx * dx + dy * dy
            t = np.clip(((x - ax) * dx + (y - ay) * dy) / n, 0.0, 1.0) if n > 0 else 0.0
            hit |= (x - ax - t * dx) ** 2 + (y - ay - t * dy) ** 2 < r2
        return hit
