"""The person tracker: the scan's unexplained returns in, tracked people out."""
from __future__ import annotations

import numpy as np

from hw.people import Person
from perception.people.config import PeopleConfig


class PersonTracker:
    """Tracks people on the lidar scan, at the scan rate."""

    def __init__(self, config: PeopleConfig):
        self.config = config

    def update(self, stamp: float, points: np.ndarray, robot: tuple[float, float, float],
               explained: np.ndarray) -> tuple[Person, ...]:
        """One scan: ``stamp`` its time (s, the runtime's clock), ``points`` its valid returns
        as (N, 2) in the odom frame, ``robot`` the robot's odom pose (x, y, yaw), ``explained``
        an (N,) bool mask of the returns the map or a known pot accounts for. Returns the
        current people (odom frame), confirmed or not, each with its confidence."""
        return ()
