"""MPU9250 IMU (+ AK8963 magnetometer through the I2C bypass): the HAL's Imu.

Reference: WHO_AM_I 0x75 = 0x71 (some boards report 0x70/0x73: accepted, warned); PWR_MGMT_1
0x6B wakes it (clock from the gyro PLL); full scales in bits 4:3 of ACCEL_CONFIG / GYRO_CONFIG;
14 bytes from ACCEL_XOUT_H are accel xyz, temp, gyro xyz, big-endian int16. Accel LSB/g
16384 >> fs, gyro LSB/(deg/s) 131 / 2^fs, temp C = raw / 333.87 + 21. The AK8963 appears at
0x0C once INT_PIN_CFG bit 1 (bypass) is set: WIA 0x48, CNTL1 0x16 (16 bit, 100 Hz), data
little-endian at 0x03..0x08, and ST2 must be read after the data to release the next sample.
"""
from __future__ import annotations

import logging
import math
from typing import Callable

import numpy as np

from hw.drivers.i2c import device_error, probe
from hw.errors import InputError
from hw.interfaces import ImuReading

G = 9.80665
GYRO_CONFIG, ACCEL_CONFIG, INT_PIN_CFG, ACCEL_XOUT_H, PWR_MGMT_1, WHO_AM_I = 0x1B, 0x1C, 0x37, 0x3B, 0x6B, 0x75
ACCEL_RANGES, GYRO_RANGES = (2, 4, 8, 16), (250, 500, 1000, 2000)
AK_WIA, AK_HXL, AK_CNTL1, AK_ID, AK_MODE = 0x00, 0x03, 0x0A, 0x48, 0x16
AK_UT_PER_LSB = 0.15

log = logging.getLogger(__name__)


class Mpu9250:
    def __init__(self, bus, address: int = 0x68, accel_range_g: int = 2, gyro_range_dps: int = 250,
                 accepted_who_am_i=(0x71, 0x70, 0x73), mag_address: int = 0x0C,
                 clock: Callable[[], float] = lambda: 0.0):
        if accel_range_g not in ACCEL_RANGES or gyro_range_dps not in GYRO_RANGES:
            raise ValueError(f"MPU9250 ranges: accel one of {ACCEL_RANGES} g, gyro one of {GYRO_RANGES} deg/s")
        self.bus, self.address, self.mag_address = bus, address, mag_address
        self.accel_fs, self.gyro_fs = ACCEL_RANGES.index(accel_range_g), GYRO_RANGES.index(gyro_range_dps)
        self.accel_scale = G / (16384 >> self.accel_fs)
        self.gyro_scale = math.radians(1.0) / (131.0 / (1 << self.gyro_fs))
        self.accepted = tuple(accepted_who_am_i)
        self.clock = clock
        self.has_mag = False

    def start(self) -> int:
        who = probe(self.bus, self.address, "MPU9250 IMU", WHO_AM_I)
        if who not in self.accepted:
            raise InputError(f"MPU9250 IMU at 0x{self.address:02x}: WHO_AM_I 0x{who:02x}, expected one of "
                             + ", ".join(f"0x{w:02x}" for w in self.accepted))
        if who != self.accepted[0]:
            log.warning("MPU9250 at 0x%02x reports WHO_AM_I 0x%02x (not 0x%02x): accepted",
                        self.address, who, self.accepted[0])
        a = self.address
        try:
            self.bus.write_byte_data(a, PWR_MGMT_1, 0x01)
            self.bus.write_byte_data(a, ACCEL_CONFIG, self.accel_fs << 3)
            self.bus.write_byte_data(a, GYRO_CONFIG, self.gyro_fs << 3)
            self.bus.write_byte_data(a, INT_PIN_CFG, 0x02)
        except OSError as exc:
            raise device_error("MPU9250", a, exc) from None
        try:
            self.has_mag = self.bus.read_byte_data(self.mag_address, AK_WIA) == AK_ID
            if self.has_mag:
                self.bus.write_byte_data(self.mag_address, AK_CNTL1, AK_MODE)
        except OSError:
            self.has_mag = False
        if not self.has_mag:
            log.warning("AK8963 magnetometer not found at 0x%02x behind the MPU9250 bypass", self.mag_address)
        return who

    def read_raw(self) -> tuple[np.ndarray, float, np.ndarray]:
        try:
            block = bytes(self.bus.read_i2c_block_data(self.address, ACCEL_XOUT_H, 14))
        except OSError as exc:
            raise device_error("MPU9250", self.address, exc) from None
        v = np.frombuffer(block, dtype=">i2").astype(np.float64)
        return v[0:3] * self.accel_scale, v[3] / 333.87 + 21.0, v[4:7] * self.gyro_scale

    def read(self) -> ImuReading:
        accel, _, gyro = self.read_raw()
        return ImuReading(self.clock(), tuple(float(x) for x in accel), tuple(float(x) for x in gyro))

    def read_temperature(self) -> float:
        return float(self.read_raw()[1])

    def read_mag(self) -> tuple[float, float, float] | None:
        """Magnetic field, microtesla (AK8963 axes), or None without a magnetometer."""
        if not self.has_mag:
            return None
        try:
            block = bytes(self.bus.read_i2c_block_data(self.mag_address, AK_HXL, 7))  # data + ST2
        except OSError as exc:
            raise device_error("AK8963", self.mag_address, exc) from None
        v = np.frombuffer(block[:6], dtype="<i2").astype(np.float64) * AK_UT_PER_LSB
        return tuple(float(x) for x in v)
