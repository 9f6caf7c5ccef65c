"""A whole MIRTE Master V2 of device emulators, for the hardware backend and `lupin hw` tests.

I2C twins on one bus (PCA9685 0x41, INA226 0x40, MPU9250 0x68 + AK8963, five AS5600 behind
the mux at 0x70), emulated GPIO line requests for the encoders and the e-stop, the Hiwonder bus
and the RPLidar C1 on pseudo-terminals, a video file per camera and a plain file as the SPI
device. ``config`` points ``hw.devices`` at all of them.
"""
from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass, field

import cv2
import numpy as np

from hw.config import HwConfig
from hw.emulators.as5600 import As5600Twin
from hw.emulators.gpio import EmulatedLineRequest
from hw.emulators.hiwonder_bus import EmuServo, HiwonderBusEmulator
from hw.emulators.i2c_bus import I2cBusTwin, Tca9548aTwin
from hw.emulators.ina226 import Ina226Twin
from hw.emulators.mpu9250 import Ak8963Twin, Mpu9250Twin
from hw.emulators.pca9685 import Pca9685Twin
from hw.emulators.rplidar import RplidarEmulator


def write_video(path, w=160, h=120, frames=6) -> str:
    vw = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 30, (w, h))
    for i in range(frames):
        vw.write(np.full((h, w, 3), 30 * i, np.uint8))
    vw.release()
    return str(path)


@dataclass
class EmulatedRobot:
    config: HwConfig
    bus: I2cBusTwin
    pwm: Pca9685Twin
    power: Ina226Twin
    imu: Mpu9250Twin
    joints: dict[str, As5600Twin]
    servo_bus: HiwonderBusEmulator
    lidar: RplidarEmulator
    led_path: str
    requests: dict[tuple[str, tuple[int, ...]], EmulatedLineRequest] = field(default_factory=dict)

    def gpio_request(self, chip, offsets, pull_up=True):
        req = EmulatedLineRequest(offsets)  # all low: encoders at 00, the NC e-stop closed (released)
        self.requests[(chip, tuple(offsets))] = req
        return req

    def line_request(self, offset: int) -> EmulatedLineRequest:
        return next(r for r in self.requests.values() if offset in r.offsets)

    def boundaries(self) -> dict:
        return {"i2c_bus": self.bus, "gpio_request": self.gpio_request}


def emulated_robot(stack: ExitStack, tmp_path, *, servo_ids=(2, 3, 4, 5, 6), lidar_points=200) -> EmulatedRobot:
    bus = I2cBusTwin()
    pwm = bus.attach(0x41, Pca9685Twin())
    power = bus.attach(0x40, Ina226Twin(0.010))
    power.set(12.4, 1.2)
    imu = bus.attach(0x68, Mpu9250Twin())
    bus.attach(0x0C, Ak8963Twin(imu))
    mux = bus.attach(0x70, Tca9548aTwin())
    joints = {j: mux.attach(ch, 0x36, As5600Twin(raw=1000 + 100 * ch))
              for j, ch in {"gripper": 0, "shoulder_pan": 1, "shoulder_lift": 2, "elbow": 3, "wrist": 4}.items()}
    servo_bus = stack.enter_context(HiwonderBusEmulator({i: EmuServo() for i in servo_ids}))
    lidar = stack.enter_context(RplidarEmulator(points=lidar_points, rate_hz=20.0))
    video = write_video(tmp_path / "cam.avi")
    led = tmp_path / "spidev"
    led.write_bytes(b"")
    config = HwConfig.model_validate({"devices": {
        "servo_bus": {"port": servo_bus.path, "timeout_s": 0.2},
        "lidar": {"port": lidar.path, "spinup_s": 1.0, "timeout_s": 0.3},
        "cameras": {"front": {"device": video, "width": 160, "height": 120, "fps": 30},
                    "wrist": {"device": video, "width": 80, "height": 60, "fps": 10}},
        "leds": {"device": str(led)},
    }})
    return EmulatedRobot(config, bus, pwm, power, imu, joints, servo_bus, lidar, str(led))
