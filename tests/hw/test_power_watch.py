"""The power watch: the robot's 2 Hz task that runs the seed's power policy on the monitor."""
from __future__ import annotations

import logging

from hw.devices_config import Ina226Config
from hw.interfaces import DeviceError, PowerReading
from hw.power_policy import RATE, PowerWatch


class Monitor:
    def __init__(self):
        self.voltage, self.error = 12.5, None

    def read(self):
        if self.error is not None:
            raise self.error
        return PowerReading(0.0, self.voltage, 1.0)


def test_power_low_after_20_s_below_11_1_v_then_turn_off_10_s_later(caplog):
    monitor = Monitor()
    watch = PowerWatch(Ina226Config(), monitor, logging.getLogger("test.power"))
    t, dt = 0.0, 1.0 / RATE
    watch.tick(t)
    assert not watch.state.low and 35.0 < watch.state.percentage < 36.0
    monitor.voltage = 11.0
    with caplog.at_level(logging.WARNING, logger="test.power"):
        while not watch.state.low:
            t += dt
            watch.tick(t)
        assert t == 1.0 / RATE + 20.0  # first sample below at 0.5 s, low 20 s later
        while not watch.state.turn_off:
            t += dt
            watch.tick(t)
    assert t == 1.0 / RATE + 30.0
    assert [r.levelname for r in caplog.records] == ["WARNING", "ERROR"]  # each said once


def test_an_unreadable_monitor_keeps_the_last_state_and_is_logged_once(caplog):
    monitor = Monitor()
    watch = PowerWatch(Ina226Config(), monitor, logging.getLogger("test.power"))
    monitor.voltage = 11.0
    for k in range(50):
        watch.tick(k * 0.5)
    assert watch.state.low
    monitor.error = DeviceError("INA226 did not answer")
    caplog.clear()
    with caplog.at_level(logging.ERROR, logger="test.power"):
        for k in range(50, 60):
            watch.tick(k * 0.5)
    assert watch.state.low and len(caplog.records) == 1
    monitor.error, monitor.voltage = None, 12.0
    watch.tick(30.0)
    assert not watch.state.low
