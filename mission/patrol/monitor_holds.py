"""Monitor holds: each time the collision monitor held the base back during a patrol, for the
report's ``holds`` list (where, how long the robot waited and how long it drove slowed, and
``lost_s``: the time the withheld share of the commanded speed amounts to, the integral of
``1 - scale``).

The monitor does not know a person from a cart, a pot or a wall, and neither does this: a hold
is any stretch of the monitor stopping or slowing the base, closed once it has let the base
drive freely for ``GAP`` seconds (so a person walking past, stopping it twice in a second, is
one hold). That is why these are not the report's ``people`` (spec/report.md: holds for pots and
walls are reported apart; issue 28: counting every hold as a person flattered the figures);
``mission.patrol.person_encounters`` counts the people the robot's tracker follows.
"""
from __future__ import annotations

from typing import Callable

from hw.collision_monitor import NONE, STOP, Verdict
from hw.odometry import Pose2D

GAP = 1.0
"""Seconds of free driving that end a hold."""

RATE = 10.0
"""Checks per second: the base controller's beat, at which the monitor judges."""


class MonitorHolds:
    def __init__(self, verdict: Callable[[], Verdict], pose: Callable[[], Pose2D], t0: float):
        self.verdict, self.pose, self.t0 = verdict, pose, t0
        self.done: list[dict] = []
        self._open: dict | None = None
        self._last: float | None = None
        self._clear_since: float | None = None

    def tick(self, now: float) -> None:
        dt, self._last = (0.0 if self._last is None else now - self._last), now
        v = self.verdict()
        if v.action == NONE:
            if self._open is not None:
                self._clear_since = self._clear_since if self._clear_since is not None else now
                if now - self._clear_since >= GAP:
                    self._close()
            return
        self._clear_since = None
        if self._open is None:
            p = self.pose()
            self._open = {"t": round(now - self.t0, 2), "x": round(p.x, 2), "y": round(p.y, 2),
                          "waited_s": 0.0, "slowed_s": 0.0, "lost_s": 0.0, "nearest_m": v.nearest}
        key = "waited_s" if v.action == STOP else "slowed_s"
        self._open[key] += dt
        self._open["lost_s"] += dt * (1.0 - v.scale)  # the share of the commanded speed withheld
        self._open["nearest_m"] = min(self._open["nearest_m"], v.nearest)

    def _close(self) -> None:
        self.done.append(self._shown(self._open))
        self._open, self._clear_since = None, None

    @staticmethod
    def _shown(e: dict) -> dict:
        return {**e, "waited_s": round(e["waited_s"], 2), "slowed_s": round(e["slowed_s"], 2),
                "lost_s": round(e["lost_s"], 2),
                "nearest_m": round(e["nearest_m"], 3) if e["nearest_m"] != float("inf") else None}

    # -- the report observer -------------------------------------------------------------------
    def recorded(self, pot, entry: dict, kinds: list[str]) -> None:
        pass

    def sections(self) -> dict:
        """``holds``: every hold so far, the one in progress included."""
        return {"holds": self.done + ([self._shown(self._open)] if self._open is not None else [])}

    def finished(self, doc: dict) -> None:
        pass
