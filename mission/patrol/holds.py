"""What holds the mission still: the e-stop latch and the operator's pause, and ``resume``.

The original's e-stop was decorative (the hardware seed): nothing froze the mission or
cancelled the goal. Here the wheels stop in the base controller on the next control tick
whatever the mission does (``hw.base_controller``), and the mission tree's first guard asks
:meth:`MissionHolds.estop` on every tick: while it gives a reason, the tree holds (its running
leaves cancel the navigation goal and hold the arm).

Releasing the button does not restart anything (ISO 13850 practice): the latch stays set until
the operator says ``resume`` with the e-stop released. A ``resume`` while the e-stop is still
engaged is refused, with the reason. The same ``resume`` ends a ``pause``. An engagement the
mission's tick did not see (a press shorter than 0.1 s, seen by the base controller's live
read) still latches: the bridge counts every engagement it sees.

Times: the log says when on the runtime clock, the one every log line is stamped with (a resume
logged at 90.2 s says ``t=90.2``, not the mission's own 45.4); the report's ``estop_events``
count from the mission's start, as every time in the report does.
"""
from __future__ import annotations

import logging
from typing import Callable

from hw.estop import EStopBridge

log = logging.getLogger(__name__)


class MissionHolds:
    def __init__(self, estop: EStopBridge, now: Callable[[], float], t0: float):
        self.bridge, self.now, self.t0 = estop, now, t0
        self.latched = False
        self.paused = False
        self.estop_events: list[dict] = []
        """Every change the mission saw, ``{"t", "engaged"}``, t from the mission's start (the
        report's ``estop_events``)."""
        self._engaged = False
        self._engagements = estop.engagements

    def estop(self) -> str | None:
        """Why the e-stop holds the mission now, or None."""
        engaged = self.bridge.engaged()
        missed = self.bridge.engagements != self._engagements
        self._engagements = self.bridge.engagements
        if engaged != self._engaged or missed:
            if missed and not engaged:  # pressed and released between two mission ticks
                self._record(True)
            self._record(engaged)
        if engaged or missed:
            self.latched = True
        if engaged:
            return "e-stop engaged"
        if self.latched:
            return "e-stop released: waiting for the operator's resume"
        return None

    def pause_reason(self) -> str | None:
        return "paused by the operator: waiting for resume" if self.paused else None

    def pause(self) -> None:
        if not self.paused:
            log.info("mission paused by the operator at t=%.1f", self.now())
        self.paused = True

    def resume(self) -> str | None:
        """Clear the latch (e-stop released) and the pause; the reason when refused."""
        if self.bridge.engaged():
            log.warning("resume refused: the e-stop is still engaged")
            return "resume refused: the e-stop is still engaged (release it first)"
        if self.latched or self.paused:
            log.info("mission resumed by the operator at t=%.1f", self.now())
        self.latched = self.paused = False
        return None

    def _record(self, engaged: bool) -> None:
        self._engaged = engaged
        self.estop_events.append({"t": round(self.now() - self.t0, 3), "engaged": engaged})
