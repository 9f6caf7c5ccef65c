"""People near the robot, as data: what the person tracker (``perception.people``) hands down to
navigation's person layer and to the safety rules below the mux.

``hw`` never imports perception (DESIGN.md): the tracker's output crosses the layers as this
plain record, and whoever assembles the runtime passes a ``Callable[[], Sequence[Person]]`` to
the parts that need it. Positions are in the ``odom`` frame: smooth and continuous, as the local
costmap and the base's own motion are (a SLAM correction never makes a person jump).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence


@dataclass(frozen=True)
class Person:
    """One tracked person (or a cart a person pushes: one body that moves with them)."""

    id: int
    """The track's id, stable while the tracker follows the same person."""
    x: float
    y: float
    """Centre of the body on the floor, odom frame, m."""
    vx: float
    vy: float
    """Velocity, odom frame, m/s (0 for someone standing)."""
    radius: float
    """Radius of a circle holding what the lidar sees of the body (legs, cart, a crouching
    worker's whole outline), m."""
    confidence: float
    """0..1: how sure the tracker is that this is a person (an unknown thing near the path
    that is neither in the map nor a known pot starts as a person until shown otherwise)."""

    def gap(self, x: float, y: float, radius: float) -> float:
        """Body to body from a round body of ``radius`` centred at (``x``, ``y``), odom, m: what
        every distance rule for people measures."""
        return math.hypot(self.x - x, self.y - y) - self.radius - radius


PeopleSource = Callable[[], Sequence[Person]]
"""What the consumers hold: the tracker's current people, read when they need them."""


def nobody() -> Sequence[Person]:
    """The source when no tracker runs."""
    return ()
