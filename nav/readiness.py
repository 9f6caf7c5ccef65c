"""The readiness cascade: navigation activates only once scans flow, a map exists and
``map -> odom -> base_link`` resolves.

The seed's biggest "why": Nav2 configured against a transform SLAM had not published yet threw
once, stayed inactive with no retry and wedged the whole lifecycle manager; on a cold start over
WiFi the transform was missing for ~5-10 s. The original chained three sentinels (wait_for_scan
-> wait_for_map -> wait_for_tf), each firing the next stage when its event arrived, and raised
the lifecycle bond timeout from 4 s to 20 s. Here the stages are checked in that order on every
beat, so each fires as soon as its event has happened (no fixed sleeps), and the 20 s ceiling
turns a stage that never comes into a message that names it (``status``) without ever giving
up: if the lidar is plugged in after a minute, navigation activates then. Once active it stays
active; the map reset's gap is bridged by odometry, not by deactivating.
"""
from __future__ import annotations

import logging
from typing import Callable

log = logging.getLogger(__name__)

#: Stage name -> what a missing stage means to an operator.
HINTS = {
    "scans": "no lidar scans (is the lidar connected and spinning?)",
    "map": "no map yet (SLAM has not produced one, or the saved map did not load)",
    "transform": "map -> odom -> base_link does not resolve (localisation has not converged)",
}


class Readiness:
    def __init__(self, checks: dict[str, Callable[[], bool]], ceiling: float):
        """``checks`` in cascade order: stage name -> has its event happened?"""
        self.checks = checks
        self.ceiling = ceiling
        self.active = False
        self.waiting_for: str | None = next(iter(checks), None)
        self._since: float | None = None
        self._reported = False

    def tick(self, now: float) -> bool:
        """Advance the cascade as far as the events allow; True once active."""
        if self.active:
            return True
        if self._since is None:
            self._since = now
        for stage, done in self.checks.items():
            if not done():
                if stage != self.waiting_for:
                    self.waiting_for, self._since, self._reported = stage, now, False
                self._overdue(now)
                return False
        self.active, self.waiting_for = True, None
        log.info("navigation active: scans, map and transform all present")
        return True

    def overdue(self, now: float) -> bool:
        """True when the stage being waited for has taken longer than the ceiling."""
        return not self.active and self._since is not None and now - self._since >= self.ceiling

    def status(self, now: float) -> str:
        if self.active:
            return "active"
        waited = 0.0 if self._since is None else now - self._since
        if self.overdue(now):
            return f"inactive: {HINTS.get(self.waiting_for, self.waiting_for)}; waited {waited:.0f} s at '{self.waiting_for}' (ceiling {self.ceiling:g} s)"
        return f"inactive: waiting for {self.waiting_for} ({waited:.1f} s)"

    def _overdue(self, now: float) -> None:
        if self.overdue(now) and not self._reported:
            self._reported = True
            log.warning("navigation %s", self.status(now))
