"""Which of a scan's returns fall on people: SLAM registers and maps the rest (issue 28).

A person is neither the greenhouse nor still for long, and a cart pushed against the robot is
worse than noise: its box stays where it is in the lidar's frame while the cart shoves the robot
along the floor with its wheels still. Registration, guessing "no motion" from the wheels, matched
the box and found none: safety.people seed 2 at 1,262 s, a cart that does not yield carried the
robot 0.94 m north in 4 s, SLAM's corrections stayed at 1-3 cm a scan in no steady direction,
the map pose ended a metre off, and the pots, now where the map said nothing stood, were taken
for people for the rest of the patrol. And a worker standing at a bench for a minute was written
into the map, which the tracker then had to cut back out (``mission.runtime.people``).

So the returns within the body (their radius and ``MARGIN``) of a tracked person pressing on the
robot (``Pressing``) are neither registered nor drawn. Only theirs, and only for a while: left out
of SLAM for good, every tracked person (stop 52's experiment 5473270) or every one who moved in
the last 5 s (c4cc6d6) was never mapped, so never explained by the map, so never dropped when
the tracker was wrong: on safety.people's seed 101 a false person beside the robot held it from
120 s to the battery's end. A shove is seconds of contact; a false person the map must explain
soon. Whether the scan can be trusted at all is still judged on every return
(``hw.scan_trust``): a person close by is something seen, not a blinded lidar. The people are
those the distance rules act on (``mission.runtime.people.People.confident``) that press on the
robot, as the tracker last saw them: the costmaps, the people guard and the collision monitor
read the whole scan.
"""
from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from hw.odometry import Pose2D
from hw.people import PeopleSource, Person

PRESS = 0.1
"""A person this near the robot's body (the tracker's circle, body to body), m, may be pushing it."""
PRESS_FOR = 8.0
"""How long one person's returns are left out at most while they keep pressing, s: seed 2's shove
lasted 4 s. Out of contact longer than this, a new press starts a new while."""
KEPT = 64
"""People remembered pressing, the latest last."""

MARGIN = 0.15
"""Past a person's radius, returns this near them are theirs too, m: the tracker's people are a
scan old when SLAM takes the next one, and a brisk walker covers 0.1 m in that time."""


class Pressing:
    """The people of ``people`` pressing on the robot (within ``PRESS`` of its body, ``gap``),
    each for at most ``PRESS_FOR`` s of a press (``clock``): a ``PeopleSource`` for SLAM."""

    def __init__(self, people: PeopleSource, gap: Callable[[Person], float], clock: Callable[[], float]):
        self.people, self.gap, self.clock = people, gap, clock
        self._press: dict[int, tuple[float, float]] = {}
        """Each pressing person's press: (since, last seen pressing), by id, the latest last."""

    def __call__(self) -> list[Person]:
        now, out = self.clock(), []
        for p in self.people():
            if self.gap(p) > PRESS:
                continue
            since, last = self._press.pop(p.id, (now, now))
            if now - last > PRESS_FOR:
                since = now
            self._press[p.id] = (since, now)
            if now - since <= PRESS_FOR:
                out.append(p)
        while len(self._press) > KEPT:
            del self._press[next(iter(self._press))]
        return out


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
