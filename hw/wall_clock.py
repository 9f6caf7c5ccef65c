"""The hardware clock: monotonic wall time, and the only place the runtime sleeps."""
from __future__ import annotations

import time


class WallClock:
    deterministic = False
    """Time runs on regardless: nothing may wait on a slow peer (SLAM runs free)."""

    def __init__(self) -> None:
        self._t0 = time.monotonic()

    def now(self) -> float:
        return time.monotonic() - self._t0

    def wait_until(self, t: float) -> None:
        delay = t - self.now()
        if delay > 0:
            time.sleep(delay)
