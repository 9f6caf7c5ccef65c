"""The hardware backend: the real MIRTE Master V2's devices behind the HAL, on the wall clock.

``HwBackend(config)`` opens every device named in ``hw.devices`` (``hw.devices_config``) in a
fixed order and wires the drivers into a ``hw.interfaces.Hal``: the same base controller, mux,
e-stop bridge and arm code then run on it as on the sim. Anything missing at start-up (a bus,
a chip that does not answer or is the wrong chip, a serial port, a silent servo or lidar, a
camera, a GPIO chip) is one ``InputError`` naming the device and where it was looked for; the
CLI prints it on one line and exits 2. Devices opened before the failure are closed again.

The boundaries that cannot run off the robot are parameters, so tests hand in emulators:
``i2c_bus`` (an smbus2-compatible object; default ``smbus2.SMBus(n)``), ``gpio_request``
(``(chip, offsets, pull_up) -> line request``; default libgpiod) and ``capture_factory``
(default ``cv2.VideoCapture``). Serial devices need nothing: give a pseudo-terminal's path as
the port. ``sleep`` is the only wait (the PCA9685 oscillator settle, the H-bridge reversal pause).

The wheels are watched from a thread of their own (``hw.wheel_watchdog``): a control loop that
stops writing while they turn has them cut within ``hw.devices.pwm.watchdog_s``.

``close()`` stops the lidar (STOP: the motor must not spin on after exit) and releases the rest;
``build_hw_hal`` also registers it to run at interpreter exit.
"""
from __future__ import annotations

import atexit
import logging
import time
from typing import Callable

import cv2

from hw.config import HwConfig
from hw.drivers.button import GpioButton
from hw.drivers.camera import OpenCvCamera
from hw.drivers.gpio import request_inputs
from hw.drivers.hbridge import HBridgeWheels
from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.i2c import open_bus
from hw.drivers.ina226 import Ina226
from hw.drivers.led_strip import SpiLedStrip
from hw.drivers.mpu9250 import Mpu9250
from hw.drivers.pca9685 import Pca9685
from hw.drivers.quadrature import QuadratureEncoders
from hw.drivers.rplidar import RplidarC1
from hw.errors import InputError
from hw.estop import warn_unverified_polarity
from hw.interfaces import DeviceError, Hal
from hw.wall_clock import WallClock
from hw.wheel_watchdog import WheelWatchdog

log = logging.getLogger(__name__)


class HwBackend:
    def __init__(self, config: HwConfig, *, i2c_bus=None, gpio_request: Callable | None = None,
                 capture_factory=cv2.VideoCapture, clock=None, sleep: Callable[[float], None] = time.sleep):
        self.config = config
        self.clock = clock or WallClock()
        self._closers: list[Callable[[], None]] = []
        try:
            self._open(config, i2c_bus, gpio_request or request_inputs, capture_factory, sleep)
        except BaseException:
            self.close()
            raise

    def _open(self, config: HwConfig, i2c_bus, gpio_request, capture_factory, sleep) -> None:
        dev, now = config.devices, self.clock.now
        self.i2c = i2c_bus if i2c_bus is not None else open_bus(dev.i2c.bus)
        if i2c_bus is None:
            self._closers.append(self.i2c.close)

        self.pwm = Pca9685(self.i2c, dev.pwm.address, dev.pwm.oscillator_hz, sleep)
        self.pwm.start(dev.pwm.frequency_hz)
        self._closers.append(self._pwm_off)
        self.power = Ina226(self.i2c, dev.power.address, dev.power.shunt_ohm, dev.power.max_expected_current,
                            dev.power.averaging, now)
        self.power.start()
        self.imu = Mpu9250(self.i2c, dev.imu.address, dev.imu.accel_range_g, dev.imu.gyro_range_dps,
                           dev.imu.accepted_who_am_i, dev.imu.mag_address, now)
        self.imu.start()

        enc = dev.encoders
        offsets = [o for w in enc.lines.values() for o in w]
        self.encoders = QuadratureEncoders(gpio_request(enc.chip, offsets, pull_up=True), enc.lines)
        self._closers.append(self.encoders.close)
        self.button = GpioButton(gpio_request(dev.estop.chip, [dev.estop.line], pull_up=dev.estop.pull_up),
                                 dev.estop.line, config.estop.engaged_level)
        self._closers.append(self.button.close)
        warn_unverified_polarity(config.estop, log)
        engaged = config.estop.engaged_level
        self.wheels = HBridgeWheels(self.pwm, dev.pwm.channels, dev.pwm.reversal_pause_s, sleep,
                                    inhibit=lambda: self.button.peek() == engaged, clock=now)
        self.watchdog = WheelWatchdog(self.wheels, dev.pwm.watchdog_s).start()
        self._closers.append(self.watchdog.close)

        sb = dev.servo_bus
        self.servos = HiwonderBus.open(sb.port, sb.baud, echo=sb.echo, timeout_s=sb.timeout_s, retries=sb.retries)
        self._closers.append(self.servos.close)
        silent = [f"{joint} (id {c.id})" for joint, c in config.servos.joints.items() if not self.servos.ping(c.id)]
        if silent:
            raise InputError(f"Hiwonder servo bus on {sb.port}: no answer from {', '.join(silent)}")

        ld = dev.lidar
        self.lidar = RplidarC1.open(ld.port, ld.baud, timeout_s=ld.timeout_s, spinup_s=ld.spinup_s,
                                    stale_s=ld.stale_s, range_min=ld.range_min, range_max=ld.range_max, clock=now)
        self._closers.append(self.lidar.close)
        try:
            self.lidar.start()
        except DeviceError:
            raise InputError(f"RPLidar on {ld.port}: no scan within {ld.spinup_s + ld.timeout_s:.1f} s "
                             "(wrong port, baud rate or power)") from None

        self.cameras = {}
        for name, c in dev.cameras.items():
            cam = OpenCvCamera(name, c.device, c.width, c.height, c.fps, now, capture_factory)
            self._closers.append(cam.close)
            self.cameras[name] = cam
        self.leds = SpiLedStrip(dev.leds.device, config.leds.num_leds, dev.leds.spi_hz)
        self._closers.append(self.leds.close)

        self.hal = Hal(clock=self.clock, wheels=self.wheels, encoders=self.encoders, servos=self.servos,
                       lidar=self.lidar, imu=self.imu, power=self.power, estop_button=self.button,
                       leds=self.leds, cameras=self.cameras)

    def _pwm_off(self) -> None:
        self.pwm.all_off()

    def close(self) -> None:
        """Release in reverse order; a device that fails to close is logged, not raised."""
        while self._closers:
            closer = self._closers.pop()
            try:
                closer()
            except Exception as exc:  # closing must reach every device
                log.warning("closing %s failed: %s", getattr(closer, "__qualname__", closer), exc)

    def __enter__(self) -> "HwBackend":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def build_hw_hal(config: HwConfig, **boundaries) -> Hal:
    """The robot's HAL on real devices (``--backend hw``); closed at interpreter exit."""
    backend = HwBackend(config, **boundaries)
    atexit.register(backend.close)
    return backend.hal
