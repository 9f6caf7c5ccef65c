"""What each person walked last: where a walker who pauses will walk again (issue 28 item 2).

The tracker gives each person's velocity now; someone pausing reads a few cm/s in any
direction. But people in a greenhouse pace: a cart pusher at the end of a cross aisle turns
and walks it back, a grower who stopped for the robot walks on once it is out of their way. So
each consumer of the people (the costmaps' person layer, ``nav.people_nearby``) wraps its source
in ``Walks``, which remembers each person's last stride by id, and reads a paused person's way
from it. The tracker keeps a person's id across a moment lost (``mission.runtime.people``), so
their walk outlives their track.
"""
from __future__ import annotations

import math

from hw.people import Person, PeopleSource

#: A person faster than this strides along their walk: their velocity is remembered; slower, the
#: tracker's velocity of someone turning or pausing points anywhere (safety.people seed 4: a
#: paused cart read 0.27 m/s sideways), m/s.
STRIDING = 0.4
#: A person slower than this is not walking anywhere now (``paused``), m/s.
WALKING = 0.2
#: Walks remembered, the most lately walked: a greenhouse crew and then some.
KEPT = 64


class Walks:
    def __init__(self, people: PeopleSource):
        self.people = people
        self._last: dict[int, tuple[float, float]] = {}
        """Each person's last striding velocity (odom), by id, the latest walked last."""

    def __call__(self) -> list[Person]:
        """The people now (``PeopleSource``); each read remembers the striders' walks."""
        people = list(self.people())
        for p in people:
            if math.hypot(p.vx, p.vy) > STRIDING:
                self._last.pop(p.id, None)
                self._last[p.id] = (p.vx, p.vy)
        while len(self._last) > KEPT:
            del self._last[next(iter(self._last))]
        return people

    def last(self, person: Person) -> tuple[float, float]:
        """``person``'s velocity, or, slower than a stride, that of their last walk (odom)."""
        if math.hypot(person.vx, person.vy) > STRIDING:
            return person.vx, person.vy
        return self._last.get(person.id, (person.vx, person.vy))

    def paused(self, person: Person) -> tuple[float, float] | None:
        """The velocity of a paused person's last walk (odom); None for someone walking now, or
        who has not walked."""
        if math.hypot(person.vx, person.vy) > WALKING:
            return None
        return self._last.get(person.id)
