"""Who is up: the robots whose liveliness token (``lupin/<robot>/alive``) the link sees.

Each runtime holds its token while its link is up (``mission.link.server``); Zenoh withdraws it
when the robot's session closes or its connection dies (the router notices a dead transport
by its lease, well inside a second at zenoh's defaults), so a console, a bench or the
dispatcher learns within a second that a robot appeared or died, and a console started later
asks for the tokens already held (``history``) and finds every robot at once.

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
    def __init__(self, session: zenoh.Session, on_change: Callable[[], None] | None = None):
        self._lock = threading.Lock()
        self._up: set[str] = set()
        self.on_change = on_change
        self._sub = session.liveliness().declare_subscriber(ALIVE, self._on_sample, history=True)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        robot = str(sample.key_expr).split("/")[1]
        with self._lock:
            if sample.kind == zenoh.SampleKind.PUT:
                self._up.add(robot)
            else:
                self._up.discard(robot)
        if self.on_change is not None:
            self.on_change()

    def robots(self) -> list[str]:
        """The robots up now, by name."""
        with self._lock:
            return sorted(self._up)

    def close(self) -> None:
        self._sub.undeclare()


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
