"""Who is up: the robots whose liveliness token (``lupin/<robot>/alive``) the link sees.

Each runtime holds its token while its link is up (``mission.link.server``); Zenoh withdraws it
when the robot's session closes or its connection dies (the router notices a dead transport
by its lease, well inside a second at zenoh's defaults), so a console, a bench or the
dispatcher learns within a second that a robot appeared or died, and a console started later
asks for the tokens already held (``history``) and finds every robot at once.

A token can also go while its robot lives: the router takes a robot for dead when nothing came
from it for its lease (``mission.link.session.ROBOT_LEASE_MS``), and a machine stalled that long
(measured on this 2-core machine at load 20: three robots dropped together, the router's side,
and their tokens were back 0.0-0.05 s after the stall, the client reconnecting at once) looks the
same as a robot that died. What a wrong "gone" costs decides how long to believe it: a console
showing a robot missing for a moment costs nothing, and keeps ``grace`` 0 (a death shown within
the second); an aisle lock freed under a live robot lets another into its aisle, so the arbiter
counts a robot gone only once its token has stayed away ``grace`` seconds
(``fleet.aisle_locks.LOCK_GRACE``): a token back within it was never gone.

``stop_fleet`` is the fleet e-stop: one query on ``lupin/fleet/stop`` that every robot answers
(target ALL: by default Zenoh would ask only the nearest queryable).
"""
from __future__ import annotations

import json
import threading
from typing import Callable

import zenoh

from mission.link.wire import ALIVE, FLEET_STOP, dumps


class Roster:
    def __init__(self, session: zenoh.Session, on_change: Callable[[], None] | None = None, grace: float = 0.0):
        """``grace``: seconds a robot's token must stay away before the robot counts as gone
        (module docstring); 0: at once."""
        self._lock = threading.Lock()
        self._up: set[str] = set()
        self._leaving: dict[str, threading.Timer] = {}
        self.on_change, self.grace = on_change, grace
        self._sub = session.liveliness().declare_subscriber(ALIVE, self._on_sample, history=True)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        robot = str(sample.key_expr).split("/")[1]
        with self._lock:
            leaving = self._leaving.pop(robot, None)
            if leaving is not None:
                leaving.cancel()
            if sample.kind == zenoh.SampleKind.PUT:
                self._up.add(robot)
            elif self.grace > 0 and robot in self._up:
                timer = self._leaving[robot] = threading.Timer(self.grace, self._gone, (robot,))
                timer.daemon = True
                timer.start()
                return
            else:
                self._up.discard(robot)
        self._changed()

    def _gone(self, robot: str) -> None:
        """The grace is over: gone, unless its token came back (its timer is no longer the one kept)."""
        with self._lock:
            if self._leaving.get(robot) is not threading.current_thread():
                return
            del self._leaving[robot]
            self._up.discard(robot)
        self._changed()

    def _changed(self) -> None:
        if self.on_change is not None:
            self.on_change()

    def robots(self) -> list[str]:
        """The robots up now, by name."""
        with self._lock:
            return sorted(self._up)

    def leaving(self) -> list[str]:
        """The robots whose token is away but still within the grace: up, for now."""
        with self._lock:
            return sorted(self._leaving)

    def close(self) -> None:
        self._sub.undeclare()
        with self._lock:
            for timer in self._leaving.values():
                timer.cancel()
            self._leaving.clear()


def stop_fleet(session: zenoh.Session, timeout: float = 2.0) -> list[str]:
    """Engage every robot's soft stop; returns the robots that said they stopped."""
    stopped = []
    for reply in session.get(FLEET_STOP, payload=dumps({}), target=zenoh.QueryTarget.ALL,
                             consolidation=zenoh.ConsolidationMode.NONE, timeout=timeout):
        if reply.ok is not None:
            try:
                stopped.append(json.loads(reply.ok.payload.to_bytes())["robot"])
            except (ValueError, KeyError, TypeError):
                continue
    return sorted(stopped)
