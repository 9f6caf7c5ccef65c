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

A strider's heading is read from where they walked over the last ``HEADING_OVER`` seconds, not
the tracker's velocity now: a cart's velocity swings +-20 deg scan to scan as its box and its
pusher's legs come and go in the scan, and a lane read from it swung across the cross aisle it
walked (safety.people seed 2, 1,403 s: the lane 0.4 m east of the robot one tick and 0.2 m west
of it the next, the robot's way out of it flipping with it).
"""
from __future__ import annotations

import math
from collections import deque
from typing import Callable, NamedTuple

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
#: A turn is remembered this long after it was seen, s: the sim's pacers are back at each end
#: of their walk every 10-50 s.
TURN_KEPT = 120.0
#: A turn seen within this of one remembered is the same turn, m.
SAME_TURN = 1.0
#: How far a turning body reaches round where it stood, in tracked radii: a cart pusher's
#: tracked circle holds pusher and cart, and the cart swings round the pusher (its far corner
#: ~0.8 m from them); a person turning on the spot stays in a circle about their own.
SWEEP = 2.0
#: Someone pausing nearer the robot than this, body to body, has stopped for it, m: the sim's
#: walkers who yield stop 0.3 m short, and the tracker's gaps wander a tenth either way.
YIELDED = 0.5


class Stride(NamedTuple):
    vx: float
    vy: float
    """A person's last striding velocity, odom, m/s."""
    when: float
    walked: bool
    """Seen to walk ``HEADING_WALKED`` within ``HEADING_OVER``: only then is it a walk (``paused``)."""
    start: tuple[float, float]
    """Where this walk began (odom): the first stride after a pause or a turn."""


class Walks:
    def __init__(self, people: PeopleSource, clock: Callable[[], float] = lambda: 0.0,
                 gap: Callable[[Person], float] = lambda p: math.inf):
        """``clock``: the runtime's seconds (a pause is timed on it); ``gap``: body to body from
        the robot to a person, m (who pauses within ``YIELDED`` has stopped for the robot)."""
        self.people, self.clock, self.gap = people, clock, gap
        self._last: dict[int, Stride] = {}
        """Each person's last stride by id, the latest walked last, seen to walk or not: only
        those seen to walk turn or keep a walk (a standing worker's track, its velocity jittering
        past ``STRIDING`` a moment, turned in a 1.25 m circle round them, safety.people seed 1)."""
        self._trail: dict[int, deque[tuple[float, float, float]]] = {}
        """Each strider's (when, x, y) over the last ``HEADING_OVER`` s and one before, by id."""
        self._turns: list[tuple[float, float, float, float]] = []
        """(x, y, reach, when) of every turn seen within ``TURN_KEPT`` (odom)."""

    def __call__(self) -> list[Person]:
        """The people now (``PeopleSource``); each read remembers the striders' walks."""
        people = list(self.people())
        now = self.clock()
        for p in people:
            if self.paused(p) is not None and self.gap(p) > YIELDED:
                self._turned(p, now)
            if math.hypot(p.vx, p.vy) <= STRIDING:
                self._trail.pop(p.id, None)  # turning or pausing: the next stride's heading starts afresh
                continue
            trail = self._trail.setdefault(p.id, deque())
            if not trail or now > trail[-1][0]:
                trail.append((now, p.x, p.y))
            while len(trail) > 2 and trail[1][0] <= now - HEADING_OVER:
                trail.popleft()
            before = self._last.pop(p.id, None)
            walked = (before is not None and before.walked) \
                or math.hypot(p.x - trail[0][1], p.y - trail[0][2]) >= HEADING_WALKED
            vx, vy = self._stride(p)
            on = before is not None and now - before.when <= HEADING_OVER and before.vx * vx + before.vy * vy > 0.0
            self._last[p.id] = Stride(vx, vy, now, walked, before.start if on else (p.x, p.y))
        for kept in (self._last, self._trail):
            while len(kept) > KEPT:
                del kept[next(iter(kept))]
        return people

    def _turned(self, person: Person, now: float) -> None:
        """Remember that ``person`` turns where they pause now (the latest sight of a turn
        replaces one remembered within ``SAME_TURN``, the wider reach kept)."""
        reach = SWEEP * person.radius
        for k, (x, y, r, _) in enumerate(self._turns):
            if math.hypot(person.x - x, person.y - y) < SAME_TURN:
                self._turns[k] = (person.x, person.y, max(r, reach), now)
                return
        self._turns.append((person.x, person.y, reach, now))
        del self._turns[:-KEPT]

    def turns(self) -> list[tuple[float, float, float]]:
        """(x, y, reach) of where people turned round within the last ``TURN_KEPT`` s (odom):
        the circle a turning body sweeps (module docstring)."""
        now = self.clock()
        self._turns = [t for t in self._turns if now - t[3] <= TURN_KEPT]
        return [t[:3] for t in self._turns]

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
        """``person``'s velocity, or, slower than a stride, that of their last walk (odom), if
        they were seen to walk (``paused``)."""
        if math.hypot(person.vx, person.vy) > STRIDING:
            return self._stride(person)
        walk = self._walk(person)
        return (person.vx, person.vy) if walk is None else (walk.vx, walk.vy)

    def paused(self, person: Person) -> tuple[float, float] | None:
        """The velocity of a paused person's last walk (odom), while the pause is short enough
        to turn round in (``PAUSE``); None for someone walking now, standing, or who has not
        been seen to walk (``HEADING_WALKED``): a crouching worker's track jittering past
        ``STRIDING`` for a moment is no walk (safety.people seed 105, 1,387 s: read as one, it
        laid a lane 4 m back along the side aisle beside the robot, its only refuge from a
        cart's cross aisle, and the robot stood in the cart's way until it walked into it)."""
        walk = self._walk(person)
        if math.hypot(person.vx, person.vy) > WALKING or walk is None or self.clock() - walk.when > PAUSE:
            return None
        return walk.vx, walk.vy

    def way_back(self, person: Person) -> tuple[float, float] | None:
        """From a paused ``person`` back to where their last walk began (odom), or None when
        they are not paused (``paused``): a pacer turns and walks the whole of it again."""
        if self.paused(person) is None:
            return None
        walk = self._walk(person)
        return walk.start[0] - person.x, walk.start[1] - person.y

    def walked(self, person: Person) -> bool:
        """Has ``person`` been seen to walk (``HEADING_WALKED``), now or before a pause?"""
        return self._walk(person) is not None

    def _walk(self, person: Person) -> Stride | None:
        """``person``'s last stride if they were seen to walk, else None."""
        walk = self._last.get(person.id)
        return walk if walk is not None and walk.walked else None


def walks_of(people: PeopleSource) -> Walks:
    """``people`` as a ``Walks``: itself when it is one (the navigation's, shared), else a walk
    memory of its own with no clock (no pause ends: tests, tools)."""
    return people if isinstance(people, Walks) else Walks(people)
