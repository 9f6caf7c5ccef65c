"""A libgpiod v2 line request, emulated at its Python API: edge events and line values.

The encoders and the e-stop button are read through ``gpiod.request_lines(...)``; what the
driver sees of the chip is the request's ``wait_edge_events``, ``read_edge_events``,
``get_value(s)`` and ``release``. This twin keeps the same shapes (``EdgeEvent`` with
``event_type`` RISING_EDGE / FALLING_EDGE, ``timestamp_ns``, ``line_offset``, ``global_seqno``,
``line_seqno``; values ``Value.ACTIVE`` / ``Value.INACTIVE``) and lets a test drive the pins:
``set`` a level (an edge event if it changed), ``turn`` a quadrature encoder by n ticks, and
``lose`` events (the kernel's event buffer overflowed: the sequence numbers jump).
"""
from __future__ import annotations

import enum
import threading
from dataclasses import dataclass


class Value(enum.Enum):
    INACTIVE = 0
    ACTIVE = 1


@dataclass(frozen=True)
class EdgeEvent:
    class Type(enum.Enum):
        RISING_EDGE = 1
        FALLING_EDGE = 2

    event_type: "EdgeEvent.Type"
    timestamp_ns: int
    line_offset: int
    global_seqno: int
    line_seqno: int


#: Quadrature Gray sequence (A, B) for forward rotation: 00 -> 10 -> 11 -> 01 -> 00 (A leads).
FORWARD = ((0, 0), (1, 0), (1, 1), (0, 1))


class EmulatedLineRequest:
    def __init__(self, offsets, levels: dict[int, int] | None = None):
        self.offsets = tuple(offsets)
        self.levels = {o: 0 for o in self.offsets}
        self.levels.update(levels or {})
        self._events: list[EdgeEvent] = []
        self._global = 0
        self._line = {o: 0 for o in self.offsets}
        self._t_ns = 0
        self._lock = threading.Lock()
        self._lose = 0
        self.released = False

    # --- driving the pins ---------------------------------------------------------------
    def set(self, offset: int, level: int) -> None:
        with self._lock:
            level = int(bool(level))
            if self.levels[offset] == level:
                return
            self.levels[offset] = level
            self._global += 1
            self._line[offset] += 1
            self._t_ns += 1000
            if self._lose > 0:
                self._lose -= 1
                return
            kind = EdgeEvent.Type.RISING_EDGE if level else EdgeEvent.Type.FALLING_EDGE
            self._events.append(EdgeEvent(kind, self._t_ns, offset, self._global, self._line[offset]))

    def lose(self, n: int) -> None:
        """The next ``n`` edges happen on the pins but their events are dropped."""
        self._lose += n

    def turn(self, a: int, b: int, ticks: int) -> None:
        """Rotate the encoder on lines (a, b) by ``ticks`` quadrature steps (sign = direction)."""
        step = 1 if ticks > 0 else -1
        for _ in range(abs(ticks)):
            i = FORWARD.index((self.levels[a], self.levels[b]))
            na, nb = FORWARD[(i + step) % 4]
            self.set(a, na)
            self.set(b, nb)

    # --- the gpiod LineRequest API ------------------------------------------------------
    def wait_edge_events(self, timeout=None) -> bool:
        return bool(self._events)

    def read_edge_events(self, max_events: int | None = None) -> list[EdgeEvent]:
        with self._lock:
            n = len(self._events) if max_events is None else min(max_events, len(self._events))
            out, self._events = self._events[:n], self._events[n:]
            return out

    def get_value(self, offset: int) -> Value:
        return Value(self.levels[offset])

    def get_values(self, offsets=None) -> list[Value]:
        return [Value(self.levels[o]) for o in (offsets or self.offsets)]

    def release(self) -> None:
        self.released = True
