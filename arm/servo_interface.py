"""The servo-bus write loop: the vendor MirteMasterArmHWInterface's dead-band re-assert.

Seed ("The dead-band re-assert mechanism", the deepest why on the hardware page): at the
10 Hz controller rate the vendor interface re-sends a joint's angle only when one of two
dead-bands trips:

- SERVO_COMMAND_DIFF 0.05 rad: the controller's command changed that much since last sent;
- SERVO_MOVED_DIFF 0.05 rad: the measured position drifted that much since the joint last
  moved (its *anchor*: where it came to rest after its last write).

Three behaviours follow and are kept on purpose: gravity sag past 0.05 rad self-corrects; a
raw servo write that bypasses the controller is overwritten the next tick (so every consumer
goes through the controllers); and holding a pose costs no bus writes at all. The fourth part
is the **startup pin**: on the first complete joint state the commands take the live pose, so
nothing snaps to the controller's stale ~0 setpoint (seed: the gripper's startup-pin).

Radians <-> Hiwonder counts go through ``ServoBusConfig`` (the one conversion, shared with the
sim). A joint the bus cannot read this tick is simply not re-asserted: garbage from a device
never crashes the loop.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

from arm import limits
from arm.config import ReassertConfig
from hw.config import ServoBusConfig, ServoCalib
from hw.interfaces import DeviceError, ServoBus

#: Reads outside this are garbage, not a pose (0..1000 over 240 deg; POS_READ may dip negative).
PLAUSIBLE = (-250, 1250)


@dataclass
class JointSlot:
    """One servo's command and state, radians."""

    name: str
    calib: ServoCalib
    command: float | None = None
    """What the controllers want; None until the startup pin."""
    sent: float | None = None
    """The command last written to the bus."""
    anchor: float | None = None
    """Where the joint came to rest after it was last written (the moved dead-band's
    reference): it follows the measured position until ``settle_until``, then stays put."""
    settle_until: float = 0.0
    """End of the last move's ramp plus the settle time, runtime seconds."""
    sent_at: float = 0.0
    """When the joint was last written, runtime seconds."""
    """End of the last move's ramp plus the settle time, runtime seconds."""
    position: float | None = None
    """Latest measured position, None when the last read failed."""
    force: bool = False
    """Re-send on the next write whatever the dead-bands say (after a re-load)."""


class ServoInterface:
    """Reads joint states and re-asserts commands on the Hiwonder bus with the dead-bands."""

    def __init__(self, bus: ServoBus, servos: ServoBusConfig, reassert: ReassertConfig,
                 max_speed: float, joints: tuple[str, ...], log: logging.Logger | None = None):
        self.bus = bus
        self.servos = servos
        self.config = reassert
        self.max_speed = max_speed
        self.log = log or logging.getLogger("lupin.arm")
        self.slots = {j: JointSlot(j, servos.joints[j]) for j in joints}
        self.pinned = False
        self.now = 0.0
        self.writes = 0
        self.read_errors = 0

    # --- state ----------------------------------------------------------------------------
    def read(self, now: float) -> bool:
        """Read every joint's position; True when all of them answered."""
        self.now = now
        complete = True
        for s in self.slots.values():
            try:
                counts = self.bus.read_position(s.calib.id)
                if not PLAUSIBLE[0] <= counts <= PLAUSIBLE[1]:
                    raise ValueError(f"implausible position {counts!r} counts")
                s.position = self.servos.counts_to_rad(s.calib, counts)
                if now < s.settle_until:
                    s.anchor = s.position  # still moving from its last write
            except (DeviceError, ValueError, TypeError) as exc:
                s.position = None
                complete = False
                self.read_errors += 1
                self.log.debug("servo %s read failed: %s", s.name, exc)
        if complete and not self.pinned:
            self.pin()
        return complete

    def pin(self) -> None:
        """Hold the live pose: commands, last-sent and anchors all become the measured positions,
        so the next write sees no dead-band tripped and nothing moves."""
        for s in self.slots.values():
            s.command = s.sent = s.anchor = s.position
            s.force = False
        self.pinned = True

    def position(self, joint: str) -> float | None:
        return self.slots[joint].position

    def command(self, joint: str) -> float | None:
        return self.slots[joint].command

    def set_command(self, joint: str, rad: float) -> None:
        """Set a joint's command, clamped through ``arm.limits`` (written on the next tick)."""
        self.slots[joint].command = limits.clamp_joint(joint, rad)

    def resend(self, joint: str) -> None:
        self.slots[joint].force = True

    # --- the write loop -------------------------------------------------------------------
    def due(self, joint: str) -> tuple[bool, bool]:
        """(command changed past its dead-band, position drifted past its dead-band)."""
        s = self.slots[joint]
        if s.command is None or s.position is None:
            return False, False
        changed = s.sent is None or abs(s.command - s.sent) > self.config.command_deadband
        drifted = s.anchor is not None and abs(s.position - s.anchor) > self.config.moved_deadband
        return changed, drifted

    def write(self) -> list[str]:
        """Re-send every joint whose dead-band tripped; returns the joints written."""
        written = []
        for name, s in self.slots.items():
            changed, drifted = self.due(name)
            if not (changed or drifted or (s.force and s.command is not None and s.position is not None)):
                continue
            counts = int(round(self.servos.rad_to_counts(s.calib, s.command)))
            # A command step is ramped at the joint speed from the last command (a trajectory
            # step takes one beat); a re-assert ramps back from where the joint drifted to.
            step = abs(s.command - (s.sent if s.sent is not None and s.sent != s.command else s.position))
            ms = int(round(1000 * max(1.0 / self.config.rate, step / self.max_speed)))
            try:
                self.bus.move(s.calib.id, max(0, min(1000, counts)), ms)
            except DeviceError as exc:
                self.log.warning("servo %s: move not sent: %s", name, exc)
                continue
            self.writes += 1
            s.sent, s.anchor, s.force = s.command, s.position, False
            s.sent_at = self.now
            s.settle_until = self.now + ms / 1000.0 + self.config.settle_time
            written.append(name)
        return written
