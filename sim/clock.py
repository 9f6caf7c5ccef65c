"""The simulated clock: time moves only when someone waits for it.

``wait_until(t)`` hands the interval to an ``advance`` callback (the MuJoCo backend steps its
physics up to ``t``) and then reads the new time. Nothing here looks at the system time, so a
run is a pure function of its seed and its inputs. The wall clock for hardware lives in
``hw.wall_clock``; both satisfy ``hw.interfaces.Clock``.
"""
from __future__ import annotations

from typing import Callable


class SimClock:
    deterministic = True
    """Time is a function of the run alone: whoever shares it may wait on each other (SLAM's
    lock-step) without changing the outcome."""

    def __init__(self, advance: Callable[[float], None] | None = None, start: float = 0.0):
        self._advance = advance
        self._now = start

    def now(self) -> float:
        return self._now

    def wait_until(self, t: float) -> None:
        if t <= self._now:
            return
        if self._advance is not None:
            self._advance(t)
        self._now = t
