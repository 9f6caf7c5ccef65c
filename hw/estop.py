"""The e-stop bridge: the physical button OR the operator's soft stop, as one engaged state.

Seed (estop_bridge): the original robot's autonomous e-stop was decorative. The mission watched
a topic nothing published, the button's message had no subscribers, and the HMI STOP only
zeroed the client's own cmd_vel, so pressing either never froze the mission. The bridge closed
that seam: it ORs the physical button with the soft stop and publishes the result at 5 Hz as the
single publisher, so a late-joining consumer always converges.

Two paths out of this module, on purpose:

* ``engaged()`` reads the pin *now*. The base controller calls it on every 10 Hz tick, so the
  wheels see a press on the very next control tick, not up to 200 ms later at the next publish.
* ``publish(now)`` is the 5 Hz task: it records the state, notifies subscribers (the mission
  tree, LEDs, telemetry) and appends to ``events`` only when the state changes (the report's
  ``estop_events``).

Polarity (``EStopConfig.engaged_level``) is NOT verified on the robot (seed). The hardware
backend logs it loudly when it opens the button (``warn_unverified_polarity``; a simulation has
no pin to check, so it says nothing) precisely so someone checks it: press the button and watch the state go true; if it
does not, flip ``LUPIN_HW__ESTOP__ENGAGED_LEVEL``. A safety interlock is only real if pressing
the button actually stops the robot.

The soft stop survives a restart (``hw.soft_stop_latch``): with a latch, the bridge starts
engaged after a crash or when the operator left it engaged, and only ``set_soft(False)`` (an
operator's release) clears it.

Fail safe: if the button cannot be read (``DeviceError``/``OSError``: the GPIO line vanished, the
sim backend failed), the bridge reports ENGAGED and logs it once per failure streak.
"""
from __future__ import annotations

import logging
from typing import Callable

from hw.config import EStopConfig
from hw.interfaces import DeviceError, EStopButton
from hw.soft_stop_latch import SoftStopLatch

EStopCallback = Callable[[float, bool], None]


def warn_unverified_polarity(config: EStopConfig, log: logging.Logger) -> None:
    """The start-up banner of the hardware backend: which pin level is taken to mean PRESSED."""
    level = config.engaged_level
    bar = "!" * 72
    log.warning(
        "\n%s\n"
        "E-STOP POLARITY ASSUMED, UNVERIFIED ON THE ROBOT: pin level %d means PRESSED "
        "(level %d means released).\n"
        "Check it: press the physical e-stop and confirm the e-stop state goes ENGAGED.\n"
        "If it does not, flip it: LUPIN_HW__ESTOP__ENGAGED_LEVEL=%d (or hw.estop.engaged_level "
        "in the config file).\n%s",
        bar, level, 1 - level, 1 - level, bar,
    )


class EStopBridge:
    def __init__(self, config: EStopConfig, button: EStopButton, log: logging.Logger | None = None,
                 latch: SoftStopLatch | None = None):
        self.config = config
        self.button = button
        self.log = log if log is not None else logging.getLogger(__name__)
        self.latch = latch
        """Where the soft stop outlives the process (the runtime's state directory); None: memory only."""
        self.soft = latch.open() if latch is not None else False
        self.held_since_start = latch.reason if latch is not None else ""
        """Why the soft stop came up engaged at start-up ('' if it did not, or once released)."""
        self.state = False
        """The last *published* state (5 Hz); ``engaged()`` is the live one."""
        self.events: list[tuple[float, bool]] = []
        """(t, engaged) at every published change, starting from an implicit 'released'."""
        self._subscribers: list[EStopCallback] = []
        self.engagements = 0
        """Engagements seen by any live read: a press shorter than the mission's tick that the
        base controller saw still latches the mission (``mission.patrol.holds``)."""
        self._live = False
        self._read_failing = False

    def set_soft(self, engaged: bool) -> None:
        """The operator's soft stop (console STOP, the ``soft_estop`` event), persisted at once."""
        engaged = bool(engaged)
        if not engaged:
            self.held_since_start = ""
        if engaged != self.soft and self.latch is not None:
            self.latch.save(engaged)
        self.soft = engaged

    def restart(self) -> None:
        """As a runtime started again after a crash: the soft stop as held in memory is gone and
        is read again from the latch (memory only: released, as a runtime without one would be)."""
        self.soft = self.latch.open() if self.latch is not None else False
        self.held_since_start = self.latch.reason if self.latch is not None else ""

    def close(self) -> None:
        """A clean exit: the latch keeps the soft stop, and the next start is not taken for a crash."""
        if self.latch is not None:
            self.latch.close()

    def button_pressed(self) -> bool:
        """The button's state right now; an unreadable button counts as pressed (fail safe)."""
        try:
            level = self.button.read_level()
        except (DeviceError, OSError) as exc:
            if not self._read_failing:
                self.log.error("e-stop button unreadable (%s): treating the e-stop as ENGAGED", exc)
                self._read_failing = True
            return True
        if self._read_failing:
            self.log.warning("e-stop button readable again (level %d)", level)
            self._read_failing = False
        return int(level) == self.config.engaged_level

    def engaged(self) -> bool:
        """Live state: the button (read now) OR the soft stop."""
        # Read the button even when soft-stopped, so a failing pin is still noticed and logged.
        pressed = self.button_pressed()
        engaged = pressed or self.soft
        if engaged and not self._live:
            self.engagements += 1
        self._live = engaged
        return engaged

    def subscribe(self, callback: EStopCallback) -> None:
        """``callback(now, engaged)`` on every publish (5 Hz), changed or not."""
        self._subscribers.append(callback)

    def publish(self, now: float) -> bool:
        """The 5 Hz task: sample, record changes, notify subscribers. Returns the state."""
        engaged = self.engaged()
        if engaged != self.state:
            self.events.append((now, engaged))
            self.log.info("e-stop %s at t=%.3f", "ENGAGED" if engaged else "released", now)
        self.state = engaged
        for callback in self._subscribers:
            callback(now, engaged)
        return engaged
