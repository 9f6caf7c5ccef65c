"""Four quadrature wheel encoders on GPIO edge events: the HAL's WheelEncoders.

4x decoding (reference): state = A<<1 | B, and the tick for a transition is
``TABLE[prev << 2 | cur]`` with TABLE = [0,-1,1,0, 1,0,0,-1, -1,0,0,1, 0,1,-1,0]; transitions
that change both bits are errors (direction unknown). 1320 ticks per wheel revolution.

Events arrive in batches (one ``read_edge_events`` per ``read_ticks``, i.e. per 10 Hz control
tick), so decoding is vectorised per wheel: each event sets one line's level; the (A, B)
state after every event is the forward-fill of the last A and B levels; the table applied to
consecutive states gives the ticks. Lost events are detected two ways: a gap in a line's
``line_seqno`` (the kernel dropped events), or an edge to the level the line already had
(its opposite edge is missing). After a loss, the decoder re-reads the line values and applies
the table once more from its state to the real one: a one-bit difference recovers the tick, a
two-bit difference is counted as an illegal transition (no tick). Garbage never raises.
"""
from __future__ import annotations

import numpy as np

from hw.drivers.gpio import is_rising, level
from hw.interfaces import WHEELS, DeviceError

TABLE = np.array([0, -1, 1, 0, 1, 0, 0, -1, -1, 0, 0, 1, 0, 1, -1, 0], dtype=np.int64)
ILLEGAL = np.array([0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0], dtype=bool)


def _ffill(mask: np.ndarray, values: np.ndarray, initial: int) -> np.ndarray:
    idx = np.where(mask, np.arange(mask.size), -1)
    np.maximum.accumulate(idx, out=idx)
    return np.where(idx >= 0, values[np.maximum(idx, 0)], initial)


class QuadratureEncoders:
    def __init__(self, request, lines: dict[str, tuple[int, int]]):
        self.request = request
        self.lines = [tuple(lines[w]) for w in WHEELS]
        offsets = [o for ab in self.lines for o in ab]
        values = [level(v) for v in request.get_values(offsets)]
        self.state = np.array([values[2 * i] << 1 | values[2 * i + 1] for i in range(4)], dtype=np.int64)
        self.ticks = np.zeros(4, dtype=np.int64)
        self.illegal = np.zeros(4, dtype=np.int64)
        self.lost = np.zeros(4, dtype=np.int64)
        self._seq = {o: None for o in offsets}

    def _drain(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        events = []
        while self.request.wait_edge_events(0):
            batch = self.request.read_edge_events()
            if not batch:
                break
            events += batch
        if not events:
            empty = np.zeros(0, dtype=np.int64)
            return empty, empty, empty
        off = np.fromiter((e.line_offset for e in events), np.int64, len(events))
        lvl = np.fromiter((is_rising(e) for e in events), np.int64, len(events))
        seq = np.fromiter((e.line_seqno for e in events), np.int64, len(events))
        return off, lvl, seq

    def _seq_gaps(self, line: int, seq: np.ndarray) -> int:
        if seq.size == 0:
            return 0
        last = self._seq[line]
        self._seq[line] = int(seq[-1])
        prev = np.concatenate(([seq[0] - 1 if last is None else last], seq[:-1]))
        return int(np.clip(seq - prev - 1, 0, None).sum())

    def poll(self) -> None:
        """Decode every pending edge event."""
        try:
            off, lvl, seq = self._drain()
        except OSError as exc:
            raise DeviceError(f"wheel encoder GPIO: {exc.strerror or exc}") from None
        resync = []
        for w, (a, b) in enumerate(self.lines):
            on_a, on_b = off == a, off == b
            mine = on_a | on_b
            if not mine.any():
                continue
            is_a, lv = on_a[mine], lvl[mine]
            prev = int(self.state[w])
            A = _ffill(is_a, lv, prev >> 1)
            B = _ffill(~is_a, lv, prev & 1)
            states = np.concatenate(([prev], A << 1 | B))
            idx = states[:-1] << 2 | states[1:]
            self.ticks[w] += TABLE[idx].sum()
            duplicates = int((states[:-1] == states[1:]).sum())
            gaps = self._seq_gaps(a, seq[on_a]) + self._seq_gaps(b, seq[on_b])
            self.state[w] = states[-1]
            if duplicates or gaps:
                self.lost[w] += duplicates + gaps
                resync.append(w)
        if resync:
            self._resync(resync)

    def _resync(self, wheels: list[int]) -> None:
        for w in wheels:
            a, b = self.lines[w]
            real = level(self.request.get_value(a)) << 1 | level(self.request.get_value(b))
            i = int(self.state[w]) << 2 | real
            self.ticks[w] += TABLE[i]
            self.illegal[w] += int(ILLEGAL[i])
            self.state[w] = real

    def read_ticks(self) -> tuple[int, ...]:
        self.poll()
        return tuple(int(t) for t in self.ticks)

    def close(self) -> None:
        self.request.release()
