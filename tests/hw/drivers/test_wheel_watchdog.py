"""The wheels' watchdog (hw/wheel_watchdog.py) on the PCA9685's register-level twin: a control
loop that stops writing while the wheels turn has every output cut; a robot standing still, or
a loop that keeps writing, is left alone; the loop's next write drives again."""
from __future__ import annotations

import logging
import time

from hw.drivers.hbridge import HBridgeWheels
from hw.drivers.pca9685 import Pca9685
from hw.emulators.i2c_bus import I2cBusTwin
from hw.emulators.pca9685 import Pca9685Twin
from hw.wall_clock import WallClock
from hw.wheel_watchdog import WheelWatchdog

CHANNELS = {"front_left": (2, 3), "front_right": (1, 0), "rear_left": (6, 7), "rear_right": (5, 4)}
LIMIT = 0.5


class Clock:
    def __init__(self):
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def rig(clock=None, limit: float = LIMIT):
    """The PCA9685's twin on an emulated bus, the wheels on it and their watchdog (not started)."""
    bus = I2cBusTwin()
    twin = bus.attach(0x41, Pca9685Twin())
    pwm = Pca9685(bus, 0x41)
    pwm.start(100)
    clock = clock if clock is not None else Clock()
    wheels = HBridgeWheels(pwm, CHANNELS, reversal_pause_s=0.0, clock=clock)
    return twin, clock, wheels, WheelWatchdog(wheels, limit)


def test_wheels_left_turning_by_a_silent_loop_are_cut_once_and_the_next_write_drives(caplog):
    twin, clock, wheels, dog = rig()
    wheels.set_duties([0.4, 0.4, -0.4, 0.4])
    clock.t += LIMIT * 0.9
    assert not dog.check() and max(twin.duties()) > 0.3  # within the limit: left alone
    clock.t += LIMIT * 0.2
    with caplog.at_level(logging.ERROR, logger="hw.wheel_watchdog"):
        assert dog.check()
    assert max(twin.duties()) == 0.0 and not wheels.driving
    assert "control loop silent for 0.55 s" in caplog.text
    clock.t += 5.0
    assert not dog.check() and dog.cuts == 1  # cut once, not again and again
    wheels.set_duties([0.2, 0.2, 0.2, 0.2])  # the loop is back
    assert max(twin.duties()) > 0.15 and wheels.driving


def test_a_robot_standing_still_or_a_loop_that_keeps_writing_is_never_cut():
    twin, clock, wheels, dog = rig()
    wheels.set_duties([0.0, 0.0, 0.0, 0.0])
    clock.t += 60.0
    assert not dog.check()  # idle for a minute with the wheels still
    for _ in range(50):
        wheels.set_duties([0.3, -0.3, 0.3, -0.3])
        clock.t += 0.1  # the controller's beat
        assert not dog.check()
    assert dog.cuts == 0 and max(twin.duties()) > 0.25


def test_the_watchdog_thread_cuts_a_loop_that_stopped():
    twin, _, wheels, dog = rig(WallClock().now, 0.15)  # the backend's clock
    dog.start()
    try:
        wheels.set_duties([0.5, 0.5, 0.5, 0.5])  # and then nothing: the loop has stalled
        end = time.monotonic() + 10.0
        while max(twin.duties()) > 0.0 and time.monotonic() < end:
            time.sleep(0.02)
        assert max(twin.duties()) == 0.0 and dog.cuts == 1
    finally:
        dog.close()
