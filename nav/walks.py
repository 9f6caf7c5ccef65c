"""What each person walked last: where a walker who pauses will walk again (issue 28 item 2).

The tracker gives each person's velocity now; someone pausing reads a few cm/s in any
direction. But people in a greenhouse pace: a cart pusher at the end of a cross aisle turns
and walks it back, a grower who stopped for the robot walks on once it is out of their way. So
the navigation reads the people through one ``Walks`` (both costmaps' person layers and
``nav.people_nearby``), which remembers each person's last stride by id, and reads a paused
person's way from it. The tracker keeps a person's id across a moment lost
(``mission.runtime.people``), so their walk outlives their track. A pause longer than ``PAUSE``
is someone standing, not turning round: a worker who walked to a bench and works there
(walker-aisle-worker: kept out of their walk both ways for good, the robot never worked their
aisle again).

How far back a walker's lane reaches is how far they walked (``walked``): a cart pusher pacing a
cross aisle turns at each end and walks all of it again, so the lane behind them is the aisle
they walked, not a few seconds of it (held-out safety.people seed 4, 1,575 s: paused at the
aisle's north end, a cart pusher who does not yield had a lane 4 m long behind them; the robot
waited 4.1 m off in the aisle, outside it, and the cart came back down the aisle into it).

A strider's heading is read from where they walked over the last ``HEADING_OVER`` seconds, not
the tracker's velocity now: a cart's velocity swings +-20 deg scan to scan as its box and its
pusher's legs come and go in the scan, and a lane read from it swung across the cross aisle it
walked (safety.people seed 2, 1,403 s: the lane 0.4 m east of the robot one tick and 0.2 m west
of it the next, the robot's way out of it flipping with it).
"""
from __future__ import annotations

import math
from collections import deque
from typing import Callable

from hw.people import Person, PeopleSource

#: A person faster than this strides along their walk: their velocity is remembered; slower, the
#: tracker's velocity of someone turning or pausing points anywhere (safety.people seed 4: a
#: paused cart read 0.27 m/s sideways), m/s.
STRIDING = 0.4
#: A person slower than this is not walking anywhere now (``paused``), m/s.
WALKING = 0.2
#: Walks remembered, the most lately walked: a greenhouse crew and then some.
KEPT = 64
#: The longest pause a walker turns round in, s: the sim's walkers pause 2-8 s at each end;
#: stopped longer, they stand (``paused``).
PAUSE = 10.0
#: A strider's heading is where they walked over this long, s (module docstring).
HEADING_OVER = 1.0
#: Below this much walked over ``HEADING_OVER``, their velocity's own heading is read, m.
HEADING_WALKED = 0.3
#: The most of a walk remembered behind a walker, m: a bay's cross aisle end to end (sim.generate:
#: six rows, 6 m). Further back than that, their lane behind them is not a place they turn round in.
WALKED_BACK = 6.0


class Walks:
    def __init__(self, people: PeopleSource, clock: Callable[[], float] = lambda: 0.0):
        """``clock``: the runtime's seconds (a pause is timed on it)."""
        self.people, self.clock = people, clock
        self._last: dict[int, tuple[float, float, float]] = {}
        """Each person's last striding velocity (odom) and when, by id, the latest walked last."""
        self._trail: dict[int, deque[tuple[float, float, float]]] = {}
        """Each strider's (when, x, y) over the last ``HEADING_OVER`` s and one before, by id."""
        self._began: dict[int, tuple[float, float, bool]] = {}
        """Where each person's last walk began (odom) and whether they have paused since, by id."""

    def __call__(self) -> list[Person]:
        """The people now (``PeopleSource``); each read remembers the striders' walks."""
        people = list(self.people())
        now = self.clock()
        for p in people:
            speed = math.hypot(p.vx, p.vy)
            began = self._began.get(p.id)
            if speed <= WALKING and began is not None:
                self._began[p.id] = (began[0], began[1], True)
            if speed <= STRIDING:
                self._trail.pop(p.id, None)  # turning or pausing: the next stride's heading starts afresh
                continue
            if began is None or began[2]:  # a first stride, or one after a pause: a walk begins here
                self._began.pop(p.id, None)
                self._began[p.id] = (p.x, p.y, False)
            trail = self._trail.setdefault(p.id, deque())
            if not trail or now > trail[-1][0]:
                trail.append((now, p.x, p.y))
            while len(trail) > 2 and trail[1][0] <= now - HEADING_OVER:
                trail.popleft()
            self._last.pop(p.id, None)
            self._last[p.id] = (*self._stride(p), now)
        for kept in (self._last, self._trail, self._began):
            while len(kept) > KEPT:
                del kept[next(iter(kept))]
        return people

    def _stride(self, person: Person) -> tuple[float, float]:
        """A strider's velocity: their speed now, headed where they walked (module docstring)."""
        trail = self._trail.get(person.id)
        if not trail:
            return person.vx, person.vy
        dx, dy = person.x - trail[0][1], person.y - trail[0][2]
        walked = math.hypot(dx, dy)
        if walked < HEADING_WALKED:
            return person.vx, person.vy
        speed = math.hypot(person.vx, person.vy)
        return speed * dx / walked, speed * dy / walked

    def last(self, person: Person) -> tuple[float, float]:
        """``person``'s velocity, or, slower than a stride, that of their last walk (odom)."""
        if math.hypot(person.vx, person.vy) > STRIDING:
            return self._stride(person)
        if person.id not in self._last:
            return person.vx, person.vy
        return self._last[person.id][:2]

    def walked(self, person: Person) -> float:
        """How far ``person`` is from where their last walk began, at most ``WALKED_BACK``, m (0
        for someone who has not walked): how far back along their lane they may turn and walk
        again. A cart pusher pacing a cross aisle walks all of it, and paused at its far end
        is still coming back down all of it (module docstring)."""
        began = self._began.get(person.id)
        if began is None:
            return 0.0
        return min(math.hypot(person.x - began[0], person.y - began[1]), WALKED_BACK)

    def paused(self, person: Person) -> tuple[float, float] | None:
        """The velocity of a paused person's last walk (odom), while the pause is short enough
        to turn round in (``PAUSE``); None for someone walking now, standing, or who has not
        walked."""
        walk = self._last.get(person.id)
        if math.hypot(person.vx, person.vy) > WALKING or walk is None or self.clock() - walk[2] > PAUSE:
            return None
        return walk[:2]


def walks_of(people: PeopleSource) -> Walks:
    """``people`` as a ``Walks``: itself when it is one (the navigation's, shared), else a walk
    memory of its own with no clock (no pause ends: tests, tools)."""
    return people if isinstance(people, Walks) else Walks(people)
