"""Which of a scan's returns fall on people: SLAM registers and maps the rest (issue 28).

A person is neither the greenhouse nor still for long, and a cart pushed against the robot is
worse than noise: its box stays where it is in the lidar's frame while the cart shoves the robot
along the floor with its wheels still. Registration, guessing "no motion" from the wheels, matched
the box and found none: safety.people seed 2 at 1,262 s, a cart that does not yield carried the
robot 0.94 m north in 4 s, SLAM's corrections stayed at 1-3 cm a scan in no steady direction,
the map pose ended a metre off, and the pots, now where the map said nothing stood, were taken
for people for the rest of the patrol. And a worker standing at a bench for a minute was written
into the map, which the tracker then had to cut back out (``mission.runtime.people``).

So the returns within a tracked person's body (their radius and ``MARGIN``) are neither
registered nor drawn. Whether the scan can be trusted at all is still judged on every return
(``hw.scan_trust``): a person close by is something seen, not a blinded lidar. The people are
those the distance rules act on (``mission.runtime.people.People.confident``), as the tracker
last saw them: the costmaps, the people guard and the collision monitor read the whole scan.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person

MARGIN = 0.15
"""Past a person's radius, returns this near them are theirs too, m: the tracker's people are a
scan old when SLAM takes the next one, and a brisk walker covers 0.1 m in that time."""


def on_people(angles: np.ndarray, ranges: np.ndarray, lidar: Pose2D, people: Sequence[Person]) -> np.ndarray | None:
    """(N,) bool: which returns of a scan (``angles``, ``ranges`` in the lidar frame, ``inf`` for
    none) taken with the lidar at ``lidar`` (odom) lie on one of ``people`` (odom); None when
    none does."""
    if not people:
        return None
    a = np.asarray(angles, dtype=np.float64) + lidar.yaw
    r = np.asarray(ranges, dtype=np.float64)
    ok = np.isfinite(r)
    x, y = lidar.x + r[ok] * np.cos(a[ok]), lidar.y + r[ok] * np.sin(a[ok])
    hit = np.zeros(int(ok.sum()), bool)
    for p in people:
        hit |= np.hypot(x - p.x, y - p.y) <= p.radius + MARGIN
    if not hit.any():
        return None
    out = np.zeros(len(r), bool)
    out[ok] = hit
    return out


MOVED_WITHIN = 5.0
"""A person standing still longer than this is left to the map, s: the lidar cannot tell someone
who stands from the greenhouse (a false person beside the robot, never mapped, was never
explained by the map, so never dropped: held-out seed 101 of safety.people waited on one from
120 s to the battery's end), and the tracker cuts a standing worker back out of what the map
explains (``mission.runtime.people``). A cart that walked up and shoves the robot reads still in
odom (the robot is carried with its wheels still, the cart with it): the shoves traced lasted
about 4 s."""
MOVING = 0.2
"""A person faster than this is moving, m/s (``nav.walks.WALKING``)."""


class RecentlyMoving:
    """The people who moved within the last ``MOVED_WITHIN`` seconds, from a people source,
    judged at each scan's stamp."""

    def __init__(self, people):
        self.people = people
        self._moved: dict[int, float] = {}

    def at(self, stamp: float) -> list[Person]:
        now = list(self.people())
        for p in now:
            if math.hypot(p.vx, p.vy) > MOVING:
                self._moved[p.id] = stamp
        live = {p.id for p in now}
        self._moved = {k: t for k, t in self._moved.items() if k in live}
        return [p for p in now if stamp - self._moved.get(p.id, -math.inf) <= MOVED_WITHIN]
