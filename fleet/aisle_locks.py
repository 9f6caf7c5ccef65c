"""Aisle locks: one robot at a time in an aisle (spec/fleet.md "Aisles"), held through the router.

The dispatcher keeps the table (``AisleTable``) and answers the robots' requests as a Zenoh
queryable (``AisleLockServer``); robots ask before they enter (``mission.link.aisle_client``). One
arbiter makes a grant atomic (two robots asking for one free aisle at once cannot both get it,
which tokens or puts alone cannot promise), and it goes through the router like everything
else, so the router's access control decides who may ask: robot R only on
``lupin/fleet/aisles/ask/R``, so no robot asks, or releases, in another's name.

A request names every aisle the robot's next leg crosses and *replaces* what it holds: granted
all at once or not at all, never one by one, so no robot holds one aisle while it waits for the
next on the way (Coffman's hold-and-wait is gone wherever a leg starts on open ground). A robot
refused waits outside and asks again. The one wait it cannot avoid is a robot inside an aisle
(it inspects from there) whose next leg needs another's: when its wait closes a cycle (r1 in A
wants B, r2 in B wants A; a wait counts while fresh, ``STALE_WAIT``), the request that closed
it is answered ``yield``: that robot backs out to open ground, lets go of its aisle and plans
again, and the other goes on. A lock goes with its holder's liveliness (``lupin/<robot>/alive``,
``mission.link.roster``), once it has stayed away ``LOCK_GRACE``: a dead robot's aisles are free
within seconds, and a live robot's are not freed by a stall of the machine. ``overdue`` lists
locks held longer than a limit, for the fleet report ("a robot that holds a lock too long is
reported").
"""
from __future__ import annotations

import json
import threading
from typing import Callable

import zenoh

from mission.link.aisle_client import AISLES, ASK, AisleLockClient, Answer, ask_key
from mission.link.roster import Roster
from mission.link.wire import dumps

__all__ = ["AISLES", "ASK", "AisleLockClient", "AisleLockServer", "AisleTable", "Answer", "LOCK_GRACE", "ask_key"]


STALE_WAIT = 5.0
"""A robot's wait counts for finding a cycle this long after it last asked, s: a waiting robot
asks again every second or so, so an older wait is one it gave up (it planned another way, or
died), and must not make a later request look like a deadlock."""


LOCK_GRACE = 3.0
"""A robot's locks go once its liveliness token has stayed away this long, s
(``mission.link.roster``): a stall of the machine past the 800 ms lease drops every robot's
token at once and each is back within 0.05 s of the stall's end (measured), so 3 s rides out
stalls up to ~3.8 s, and a killed robot (its socket closed, its token gone at once) frees its
aisles 3 s later, well before anyone has driven to them."""


class AisleTable:
    """Who holds which aisle, who waits for whom; every call under one lock."""

    def __init__(self, clock: Callable[[], float]):
        self.clock = clock
        self._lock = threading.Lock()
        self._holder: dict[int, str] = {}
        self._since: dict[int, float] = {}
        self._waits: dict[str, tuple[set[str], float]] = {}

    def request(self, robot: str, aisles: list[int]) -> Answer:
        """``robot`` wants to hold exactly ``aisles`` (empty: release everything)."""
        with self._lock:
            blocked = {a: self._holder[a] for a in aisles if self._holder.get(a, robot) != robot}
            if blocked:
                self._waits[robot] = (set(blocked.values()), self.clock())
                if self._in_cycle(robot):
                    del self._waits[robot]
                    return Answer(False, blocked, yield_=True)
                return Answer(False, blocked)
            self._waits.pop(robot, None)
            now = self.clock()
            for a in [a for a, r in self._holder.items() if r == robot and a not in aisles]:
                del self._holder[a], self._since[a]
            for a in aisles:
                if a not in self._holder:
                    self._holder[a], self._since[a] = robot, now
            return Answer(True)

    def _in_cycle(self, robot: str) -> bool:
        """Does following who waits for whom (fresh waits only) from ``robot`` lead back to it?"""
        now = self.clock()
        waits = {r: who for r, (who, t) in self._waits.items() if now - t <= STALE_WAIT}
        seen, todo = set(), list(waits.get(robot, ()))
        while todo:
            r = todo.pop()
            if r == robot:
                return True
            if r not in seen:
                seen.add(r)
                todo.extend(waits.get(r, ()))
        return False

    def keep_only(self, up: set[str]) -> list[str]:
        """Free every lock of a robot not ``up``; the robots whose locks went."""
        with self._lock:
            gone = sorted({r for r in self._holder.values() if r not in up})
            for a in [a for a, r in self._holder.items() if r not in up]:
                del self._holder[a], self._since[a]
            for r in [r for r in self._waits if r not in up]:
                del self._waits[r]
            return gone

    def held(self) -> dict[int, str]:
        with self._lock:
            return dict(sorted(self._holder.items()))

    def overdue(self, limit: float) -> dict[int, tuple[str, float]]:
        """Locks held longer than ``limit`` s: aisle -> (robot, seconds held)."""
        now = self.clock()
        with self._lock:
            return {a: (r, now - self._since[a]) for a, r in sorted(self._holder.items()) if now - self._since[a] > limit}


class AisleLockServer:
    """The dispatcher's side: the table as a queryable on ``lupin/fleet/aisles/ask/*``, freed of
    dead robots by the roster, published on ``lupin/fleet/aisles`` after every change."""

    def __init__(self, session: zenoh.Session, clock: Callable[[], float], lock_grace: float = LOCK_GRACE):
        self.session, self.table = session, AisleTable(clock)
        self.roster = Roster(session, on_change=self._on_roster, grace=lock_grace)
        self._queryable = session.declare_queryable(f"{ASK}/*", self._on_query)

    def _on_query(self, query: zenoh.Query) -> None:
        robot = str(query.key_expr).rsplit("/", 1)[1]
        try:
            want = json.loads(query.payload.to_bytes()).get("aisles") if query.payload is not None else None
            aisles = sorted({int(a) for a in want})
        except (ValueError, TypeError, AttributeError):
            query.reply_err(dumps({"error": "expected {\"aisles\": [ids]}"}))
            return
        # a robot whose liveliness the dispatcher does not see holds nothing: its lock could never be freed
        a = self.table.request(robot, aisles) if robot in self.roster.robots() else Answer(False)
        query.reply(query.key_expr, a.dumps())
        if a.granted:
            self._publish()

    def _on_roster(self) -> None:
        if not hasattr(self, "roster"):  # the tokens already held, told while the roster is declared: nothing held yet
            return
        if self.table.keep_only(set(self.roster.robots())):
            self._publish()

    def free(self, robot: str) -> None:
        """Free ``robot``'s locks now: the dispatcher took its patrol off it (an e-stop held too
        long, a low battery), so it asks for nothing more and must not keep the others out."""
        if self.table.keep_only(set(self.roster.robots()) - {robot}):
            self._publish()

    def _publish(self) -> None:
        self.session.put(AISLES, dumps({str(a): r for a, r in self.table.held().items()}))

    def close(self) -> None:
        self.roster.close()
        self._queryable.undeclare()

