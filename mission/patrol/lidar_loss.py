"""A lost lidar pauses the patrol, and ends it only if the lidar does not come back.

Without scans the robot cannot see people, pots or walls: the collision monitor stops its linear
motion within a tick (``hw.collision_monitor``: a stale or blind scan is not a clear one), and
navigation holds its goal. Left at that, every remaining pot of a patrol whose lidar died would
time out as ``unreachable``, about four minutes a pot, with no fault said. So the mission holds
(``behaviours.guard.Hold``, between the e-stop and the operator's pause) once the scans have
been untrustworthy for ``lidar_lost_after`` seconds: the pot in progress stops where it is (its
goal cancelled) and starts over from its approach when scans are trusted again, so no pot is
failed for it. Past ``lidar_lost_give_up`` seconds the patrol ends ``aborted``: the remaining
pots ``skipped`` with the reason, the robot standing still where it is (it cannot see to drive
home). The report's ``faults`` list has each ``lidar_lost`` stretch.
"""
from __future__ import annotations

import logging
from typing import Callable

log = logging.getLogger(__name__)


class LidarLoss:
    def __init__(self, untrusted_since: Callable[[], float | None], now: Callable[[], float],
                 lost_after: float, give_up_after: float, armed: Callable[[], bool] = lambda: True):
        self.untrusted_since, self.now, self.armed = untrusted_since, now, armed
        """``armed``: the lidar has been seen working (navigation went active); before that a
        missing lidar is the start-up gate's to name (the readiness cascade's ``scans``)."""
        self.lost_after, self.give_up_after = lost_after, give_up_after
        self.given_up = ""
        """Why the patrol gave up on the lidar ('' while it has not): latched."""
        self._lost = False

    def lost_for(self) -> float | None:
        """Seconds the scans have been untrustworthy, once that is ``lost_after`` or more."""
        since = self.untrusted_since() if self.armed() else None
        t = None if since is None else self.now() - since
        lost = t is not None and t >= self.lost_after
        if lost != self._lost:
            self._lost = lost
            if lost:
                log.error("lidar lost (no trustworthy scan for %.1f s): the patrol is paused until scans return", t)
            else:
                log.warning("lidar back: the patrol goes on")
        return t if lost else None

    def reason(self) -> str | None:
        """Why the mission holds for the lidar now, or None (the ``Hold``'s question)."""
        t = self.lost_for()
        if t is None:
            return None
        if t >= self.give_up_after and not self.given_up:
            self.given_up = (f"lidar lost for {t:.0f} s (no trustworthy scan; patrol.lidar_lost_give_up "
                             f"{self.give_up_after:g} s): patrol aborted, the robot stands where it is")
            log.error(self.given_up)
        return f"lidar lost for {t:.0f} s: paused until scans return"
