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
        """The farthest any part of the outline is from the base centre, m (within ``margin`` of
        it: at most ``reach + margin * sqrt(2)``, the chassis' corner)."""
        self._start = capsules.segments[:, 0]
        self._along = capsules.segments[:, 1] - self._start
        length2 = np.einsum("ij,ij->i", self._along, self._along)
        self._inverse_length2 = np.divide(1.0, length2, out=np.zeros_like(length2), where=length2 > 0)

    def inside(self, x: np.ndarray, y: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Which points (x, y: arrays of one shape, base frame) lie within ``margin`` of the
        outline. All capsules at once (the arm's four one by one were 0.2 ms on a whole scan, a
        fifth of the person tracker's budget; at once 0.08). A caller with a whole scan cuts it to
        the points within ``reach`` first (``mission.runtime.people.People.on_robot``)."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        near = (np.abs(x) < self.half_length + margin) & (np.abs(y) < self.half_width + margin)
        if len(self._start):
            px, py = x[..., None] - self._start[:, 0], y[..., None] - self._start[:, 1]
            ux, uy = self._along[:, 0], self._along[:, 1]
            t = np.clip((px * ux + py * uy) * self._inverse_length2, 0.0, 1.0)
            near |= ((px - t * ux) ** 2 + (py - t * uy) ** 2 < (self.capsules.radius + margin) ** 2).any(axis=-1)
        return near
