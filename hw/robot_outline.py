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
from numba import njit


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
        self._start = np.ascontiguousarray(capsules.segments[:, 0], dtype=np.float64)
        self._along = np.ascontiguousarray(capsules.segments[:, 1] - self._start, dtype=np.float64)
        length2 = np.einsum("ij,ij->i", self._along, self._along)
        self._inverse_length2 = np.divide(1.0, length2, out=np.zeros_like(length2), where=length2 > 0)

    def inside(self, x: np.ndarray, y: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Which points (x, y: arrays of one shape, base frame) lie within ``margin`` of the
        outline. One compiled pass over the points, each tested against the box and then the
        capsules until one holds it: a whole scan costs no more than its few near returns cut
        out first did in numpy (the monitor and the person tracker test every scan)."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        out = _inside(np.ascontiguousarray(x).ravel(), np.ascontiguousarray(y).ravel(), *self.kernel(margin))
        return out.reshape(x.shape)

    def kernel(self, margin: float = 0.0) -> tuple:
        """The outline grown by ``margin`` as compiled code takes it (``holds``' arguments after
        the point): for a caller that tests points inside its own compiled pass."""
        return (self.half_length + margin, self.half_width + margin, self._start, self._along,
                self._inverse_length2, (self.capsules.radius + margin) ** 2)


@njit(cache=True)
def holds(x, y, half_length, half_width, start, along, inverse_length2, reach2):
    """Does the outline (``Outline.kernel``'s arguments) hold the base-frame point (x, y)?"""
    if abs(x) < half_length and abs(y) < half_width:
        return True
    for k in range(start.shape[0]):
        px, py = x - start[k, 0], y - start[k, 1]
        t = min(max((px * along[k, 0] + py * along[k, 1]) * inverse_length2[k], 0.0), 1.0)
        dx, dy = px - t * along[k, 0], py - t * along[k, 1]
        if dx * dx + dy * dy < reach2:
            return True
    return False


@njit(cache=True)
def _inside(x, y, half_length, half_width, start, along, inverse_length2, reach2):
    out = np.zeros(x.shape[0], np.bool_)
    for i in range(x.shape[0]):
        out[i] = holds(x[i], y[i], half_length, half_width, start, along, inverse_length2, reach2)
    return out
