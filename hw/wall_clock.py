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


class WallPace:
    """Hold another clock to wall-clock pace: ``wait(t)`` returns once as much wall time has
    passed since the first call as ``t`` is past ``start``. A real-time sim (``sim.realtime``)
    steps its physics only after this, so it runs at the robot's own pace."""

    def __init__(self, start: float = 0.0) -> None:
        self.start = start
        self._t0: float | None = None

    def wait(self, t: float) -> None:
        if self._t0 is None:
            self._t0 = time.monotonic()
        delay = (t - self.start) - (time.monotonic() - self._t0)
        if delay > 0:
            time.sleep(delay)
