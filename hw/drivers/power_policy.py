"""The seed's power policy (power_watcher): percentage, power-low, turn-off, over-current.

Seed numbers: min_voltage 11.1 V (0 %), max_voltage 15.0 V (100 %), percentage linear in
voltage between them; power-low once the pack has stayed below min_voltage for
power_low_time 20 s (a sag under a current spike is not a flat battery); turn-off once power
has been low for a further turn_off_time 10 s; over-current above max_current 5.0 A. Battery-low
is what flips the status strip and the console's battery pill. Non-finite readings (garbage
from the device) are ignored, never crash the loop, and do not reset the timers.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from hw.devices_config import Ina226Config
from hw.interfaces import PowerReading


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
