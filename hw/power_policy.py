"""The seed's power policy (power_watcher): percentage, power-low, turn-off, over-current.

``PowerPolicy`` is the rule; ``PowerWatch`` is the robot's task that samples the monitor at
``RATE`` and keeps the state every consumer reads (the mission's battery guard, the LEDs,
telemetry). On the robot the pack's turn-off is the power board's business: the watch only
says so, loudly, once.

Seed numbers: min_voltage 11.1 V (0 %), max_voltage 15.0 V (100 %), percentage linear in
voltage between them; power-low once the pack has stayed below min_voltage for
power_low_time 20 s (a sag under a current spike is not a flat battery); turn-off once power
has been low for a further turn_off_time 10 s; over-current above max_current 5.0 A. Battery-low
is what flips the status strip and the console's battery pill. Non-finite readings (garbage
from the device) are ignored, never crash the loop, and do not reset the timers.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from hw.devices_config import Ina226Config
from hw.interfaces import DeviceError, PowerMonitor, PowerReading

RATE = 2.0
"""Samples per second: the INA226 averages 256 conversions (~0.28 s per reading at its 1.1 ms
conversion time), so 2 Hz is every fresh reading and times the 20 s power-low to 0.5 s."""


@dataclass(frozen=True)
class PowerState:
    percentage: float
    low: bool
    turn_off: bool
    over_current: bool


class PowerPolicy:
    def __init__(self, config: Ina226Config):
        self.config = config
        self._below_since: float | None = None
        self._low_since: float | None = None
        self.state = PowerState(100.0, False, False, False)

    def percentage(self, voltage: float) -> float:
        c = self.config
        return float(min(100.0, max(0.0, (voltage - c.min_voltage) / (c.max_voltage - c.min_voltage) * 100.0)))

    def update(self, now: float, reading: PowerReading) -> PowerState:
        c = self.config
        v, i = reading.voltage, reading.current
        if not (math.isfinite(v) and math.isfinite(i)):
            return self.state
        if v < c.min_voltage:
            if self._below_since is None:
                self._below_since = now
            if self._low_since is None and now - self._below_since >= c.power_low_time:
                self._low_since = now
        else:
            self._below_since = self._low_since = None
        low = self._low_since is not None
        turn_off = low and now - self._low_since >= c.turn_off_time
        self.state = PowerState(self.percentage(v), low, turn_off, abs(i) > c.max_current)
        return self.state


class PowerWatch:
    """Samples ``monitor`` on the scheduler and runs the policy; an unreadable monitor keeps the
    last state (logged once per failure streak), it never stops the loop."""

    def __init__(self, config: Ina226Config, monitor: PowerMonitor, log: logging.Logger | None = None):
        self.policy = PowerPolicy(config)
        self.monitor = monitor
        self.log = log if log is not None else logging.getLogger(__name__)
        self.reading: PowerReading | None = None
        self._failing = False

    @property
    def state(self) -> PowerState:
        return self.policy.state

    def tick(self, now: float) -> None:
        try:
            reading = self.monitor.read()
        except (DeviceError, OSError) as exc:
            if not self._failing:
                self.log.error("power monitor unreadable (%s): keeping the last battery state", exc)
                self._failing = True
            return
        self._failing = False
        before = self.policy.state
        self.reading = reading
        after = self.policy.update(now, reading)
        if after.low and not before.low:
            self.log.warning("battery LOW at t=%.1f: %.2f V for %.0f s (below %.1f V)", now, reading.voltage,
                             self.policy.config.power_low_time, self.policy.config.min_voltage)
        if after.turn_off and not before.turn_off:
            self.log.error("battery TURN-OFF at t=%.1f: power low for %.0f s; the power board cuts the robot",
                           now, self.policy.config.turn_off_time)
