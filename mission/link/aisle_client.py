"""A robot's side of the aisle locks (spec/fleet.md "Aisles"): the keys, the answer, the asking.

The arbiter is the dispatcher's (``fleet.aisle_locks``); a robot only asks, on its own key
``lupin/fleet/aisles/ask/<robot>`` (the router lets nobody else ask there), for every aisle its
next leg crosses, and is told granted, refused (and by whom), or to yield. Here, below
``fleet/``, because the robot's runtime asks (``mission.patrol.aisle_gate``) and the layers
point down: the arbiter imports its wire format from here.
"""
from __future__ import annotations

import json
import threading
from dataclasses import dataclass, field

import zenoh

from mission.link.wire import dumps

AISLES = "lupin/fleet/aisles"
"""Where the dispatcher publishes who holds which aisle (JSON ``{aisle: robot}``)."""
ASK = f"{AISLES}/ask"


def ask_key(robot: str) -> str:
    """The key robot ``robot`` asks on (the router lets only it query there)."""
    return f"{ASK}/{robot}"


@dataclass(frozen=True)
class Answer:
    granted: bool
    held_by: dict[int, str] = field(default_factory=dict)
    """The aisles refused, by whom they are held."""
    yield_: bool = False
    """Back out to open ground and plan again: waiting would close a cycle."""

    def dumps(self) -> bytes:
        return dumps({"granted": self.granted, "held_by": self.held_by, "yield": self.yield_})


def read_answer(payload: bytes) -> Answer | None:
    """The arbiter's answer from its reply; None for anything else (never trusted as a grant)."""
    try:
        got = json.loads(payload)
        return Answer(bool(got["granted"]), {int(a): str(r) for a, r in got["held_by"].items()}, bool(got["yield"]))
    except (ValueError, KeyError, TypeError, AttributeError):
        return None


class Pending:
    """A request in flight, answered on Zenoh's thread: the runtime's loop polls ``answered``
    and never waits on the link."""

    def __init__(self, aisles: list[int]):
        self.aisles = sorted(aisles)
        self.answered = threading.Event()
        """Set once the arbiter replied or the query ended unanswered (``answer`` None)."""
        self.answer: Answer | None = None

    def _on_reply(self, reply: zenoh.Reply) -> None:
        if reply.ok is not None and self.answer is None:
            self.answer = read_answer(reply.ok.payload.to_bytes())


class AisleLockClient:
    """Ask for the aisles of the next leg, or let go of them all: ``ask`` waits for the
    answer (a tool, a test), ``ask_later`` does not (the runtime)."""

    def __init__(self, session: zenoh.Session, robot: str, timeout: float = 2.0):
        self.session, self.key, self.timeout = session, ask_key(robot), timeout

    def ask(self, aisles: list[int]) -> Answer | None:
        """The arbiter's answer; None when none came (no dispatcher: wait outside, ask again)."""
        for reply in self.session.get(self.key, payload=dumps({"aisles": sorted(aisles)}), timeout=self.timeout):
            if reply.ok is not None:
                return read_answer(reply.ok.payload.to_bytes())
        return None

    def ask_later(self, aisles: list[int]) -> Pending:
        pending = Pending(aisles)
        self.session.get(self.key, zenoh.handlers.Callback(pending._on_reply, pending.answered.set),
                         payload=dumps({"aisles": pending.aisles}), timeout=self.timeout)
        return pending

    def release(self) -> bool:
        a = self.ask([])
        return a is not None and a.granted
