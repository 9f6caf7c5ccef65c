"""shoulder_lift's trips: an unloaded servo is re-loaded, a latched one takes the arm out of use.

Seed: the Hiwonder LX-series shoulder_lift servo trips when held against gravity. It stalls
below the 5 A cap, pulls current with zero motion, and either

- **unloads**: torque drops, the joint goes back-drivable and the arm sags. It re-loads with
  set_enable true (here ``set_load(id, True)``), after which the joint is re-commanded; or
- **latches** (the older mode): commands are ignored while the encoder still reports. Only a
  hard power cycle clears it, so the arm is out of use until then and whoever uses it is told.

The controller asks ``inspect`` only when something looks wrong (the joint sagged past the
moved dead-band with no command change, or it is still off target after the stuck delay), so
a healthy arm costs no extra bus traffic. Unload is read from the servo; a latch shows as a
loaded servo that made no progress at all towards a target well away, or as one that stays
unloaded through every re-load.
"""
from __future__ import annotations

import logging
from enum import Enum

from arm.config import ReassertConfig, StallConfig
from arm.servo_interface import ServoInterface
from hw.interfaces import DeviceError, ServoBus


class Verdict(str, Enum):
    OK = "ok"
    RELOADED = "reloaded"
    LATCHED = "latched"


class StallWatch:
    def __init__(self, bus: ServoBus, interface: ServoInterface, config: StallConfig,
                 reassert: ReassertConfig, log: logging.Logger):
        self.bus = bus
        self.interface = interface
        self.config = config
        self.reassert = reassert
        self.log = log
        self.attempts = {j: 0 for j in config.joints}
        self.reason: str | None = None

    def watches(self, joint: str) -> bool:
        return joint in self.attempts

    def settled(self, joint: str) -> None:
        """The joint reached its command: a later trip starts its re-load count afresh."""
        if joint in self.attempts:
            self.attempts[joint] = 0

    def inspect(self, joint: str, stuck: bool, move_start: float | None) -> Verdict:
        """Look at a suspicious joint; re-load it if it unloaded. ``stuck``: off target after
        the stuck delay; ``move_start``: where the joint was when its command last changed."""
        slot = self.interface.slots[joint]
        try:
            status = self.bus.read_status(slot.calib.id)
        except DeviceError as exc:
            self.log.warning("%s: status unreadable (%s); will look again", joint, exc)
            return Verdict.OK
        if not status.loaded:
            if self.attempts[joint] >= self.config.reload_attempts:
                return self._latched(joint, f"stays unloaded after {self.attempts[joint]} re-loads")
            try:
                self.bus.set_load(slot.calib.id, True)
            except DeviceError as exc:
                self.log.warning("%s: re-load not sent: %s", joint, exc)
                return Verdict.OK
            self.attempts[joint] += 1
            self.interface.resend(joint)
            self.log.warning("%s unloaded (stall trip): re-loaded and re-commanded (try %d)",
                             joint, self.attempts[joint])
            return Verdict.RELOADED
        db = self.reassert.moved_deadband
        far = slot.command is not None and move_start is not None and \
            abs(slot.command - move_start) > self.reassert.stuck_factor * db
        if stuck and far and slot.position is not None and abs(slot.position - move_start) < db:
            return self._latched(joint, "ignores its commands while its encoder still reports")
        return Verdict.OK

    def _latched(self, joint: str, why: str) -> Verdict:
        self.reason = f"{joint} servo latched ({why}): needs a hard power cycle; arm out of use"
        self.log.error(self.reason)
        return Verdict.LATCHED
