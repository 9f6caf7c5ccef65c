"""The chassis command bus: priority arbitration of velocity sources with silence timeouts.

Seed (twist_mux.yaml): three sources feed the base through one mux, dead-man joy 100 / 0.3 s,
operator manual 50 / 0.5 s, autonomy auto 10 / 0.5 s, plus an idle zero publisher at priority 1.
Higher priority wins while live; a source that has been silent longer than its timeout stops
counting and the next-highest live source regains the bus. Nav2 never drives the wheels directly:
autonomy publishes to ``auto`` and goes through exactly the same arbitration as a human, so a
held dead-man instantly preempts it.

The mux output is the ONLY path into the base controller (``hw.base_controller``); the e-stop
sits below it and zeroes the wheels whatever the mux says.

Liveness: a source is live while ``now - last_stamp <= timeout`` (a message exactly ``timeout``
old still counts; strictly older is dead). Ages are compared in integer nanoseconds, the
resolution the scheduler keeps its beats in, so a message published on one beat and checked
exactly ``timeout`` later is live even though ``1.3 - 1.0 > 0.3`` in floats. The zero guard ("idle") is always live, so when every
real source is silent the bus outputs a zero twist rather than the last stale command. Ties in
priority go to the source listed first in the config (deterministic, never random); a source at
or below the guard's priority can never win.

While the e-stop holds, the base controller calls ``discard_until(now)`` on every tick: a twist
published before (or at) the last engaged tick never drives the base after the release, from any
source (ISO 13850: releasing a stop never restarts motion by itself; a console still holding its
stick after the release publishes again, and that fresh twist counts).

A twist with a NaN or infinite component (a planner bug, a garbled console message) is dropped
and logged, not passed on: it cannot refresh its source, so that source simply times out.
"""
from __future__ import annotations

import logging
import math

from hw.config import MuxConfig
from hw.interfaces import ZERO_TWIST, Twist

#: Name reported when the built-in zero guard holds the bus.
IDLE = "idle"

_NS = 1_000_000_000
log = logging.getLogger(__name__)


def _ns(t: float) -> int:
    return round(t * _NS)


class TwistMux:
    def __init__(self, config: MuxConfig):
        if IDLE in config.sources:
            raise ValueError(f"source name {IDLE!r} is reserved for the zero guard")
        self.config = config
        # Sorted once: highest priority first, config order breaks ties (sorted() is stable).
        self._ranked = sorted(config.sources.items(), key=lambda kv: -kv[1].priority)
        self._timeout_ns = {name: _ns(src.timeout) for name, src in config.sources.items()}
        self._last: dict[str, tuple[int, Twist]] = {}
        self._barrier_ns = -1
        """Twists stamped at or before this (ns) are void: published while the e-stop held."""

    @property
    def sources(self) -> tuple[str, ...]:
        return tuple(self.config.sources)

    def publish(self, source: str, twist: Twist, now: float) -> None:
        """Record ``twist`` from ``source`` at time ``now``."""
        if source not in self.config.sources:
            known = ", ".join(self.config.sources)
            raise ValueError(f"unknown twist_mux source {source!r} (known: {known})")
        if not all(math.isfinite(v) for v in (twist.vx, twist.vy, twist.wz)):
            log.error("twist_mux: dropped a non-finite twist from %r: %s", source, twist)
            return
        self._last[source] = (_ns(now), twist)

    def last(self, source: str) -> tuple[float, Twist] | None:
        """The last twist ``source`` published and when (None: never), live or not."""
        entry = self._last.get(source)
        return None if entry is None else (entry[0] / _NS, entry[1])

    def is_live(self, source: str, now: float) -> bool:
        last = self._last.get(source)
        if last is None or last[0] <= self._barrier_ns:
            return False
        return _ns(now) - last[0] <= self._timeout_ns[source]

    def discard_until(self, now: float) -> None:
        """Void every twist published up to ``now`` (the e-stop holds): none drives the base later."""
        self._barrier_ns = max(self._barrier_ns, _ns(now))

    def select(self, now: float) -> tuple[Twist, str]:
        """The twist on the bus at ``now`` and the name of the source that owns it."""
        guard = self.config.zero_guard_priority
        for name, src in self._ranked:
            if src.priority <= guard:
                break  # the always-live zero guard outranks everything from here down
            if self.is_live(name, now):
                return self._last[name][1], name
        return ZERO_TWIST, IDLE

    def active_source(self, now: float) -> str:
        return self.select(now)[1]
