"""Faults: each stretch a sensor fault lasted during a patrol, for the report's ``faults`` list
(spec/report.md: ``{kind, t, duration_s}``).

Each kind is a question the runtime can answer at any tick (``lidar_blind``: the collision
monitor judges the scans blind); a stretch opens the tick it is first true and closes the tick
it is false again, so a report written mid-fault shows the fault so far. Checked at the base's
beat, at which the monitor judges its scans.
"""
from __future__ import annotations

from typing import Callable

RATE = 10.0
"""Checks per second: the base controller's beat."""


class Faults:
    def __init__(self, kinds: dict[str, Callable[[], bool]], t0: float):
        self.kinds, self.t0 = kinds, t0
        self.done: list[dict] = []
        self._open: dict[str, float] = {}
        self._now = t0

    def tick(self, now: float) -> None:
        self._now = now
        for kind, active in self.kinds.items():
            if active():
                self._open.setdefault(kind, now)
            elif kind in self._open:
                self.done.append(self._entry(kind, self._open.pop(kind), now))

    def _entry(self, kind: str, start: float, end: float) -> dict:
        return {"kind": kind, "t": round(start - self.t0, 2), "duration_s": round(end - start, 2)}

    # -- the report observer -------------------------------------------------------------------
    def recorded(self, pot, entry: dict, kinds: list[str]) -> None:
        pass

    def sections(self) -> dict:
        """``faults``: every stretch so far, those still going included."""
        going = [self._entry(k, start, self._now) for k, start in self._open.items()]
        return {"faults": sorted(self.done + going, key=lambda e: e["t"])}

    def finished(self, doc: dict) -> None:
        pass
