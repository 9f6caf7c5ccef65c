"""Register-level twins of the MPU9250 IMU and its AK8963 magnetometer.

The MPU's output registers are computed from a physical state (``accel`` m/s^2, ``gyro``
rad/s, ``temp_c``) at the full scales the driver configured (ACCEL_CONFIG / GYRO_CONFIG bits
4:3), big-endian int16 as on the chip. The AK8963 is only on the bus while the MPU's
INT_PIN_CFG bypass bit is set, and reports little-endian data with ST2 read after it.
"""
from __future__ import annotations


import numpy as np

from hw.emulators.i2c_bus import RegisterDevice

G = 9.80665
GYRO_CONFIG, ACCEL_CONFIG, INT_PIN_CFG, ACCEL_XOUT_H, PWR_MGMT_1, WHO_AM_I = 0x1B, 0x1C, 0x37, 0x3B, 0x6B, 0x75


def _be16(values) -> bytes:
    return np.clip(np.round(values), -32768, 32767).astype(">i2").tobytes()


class Mpu9250Twin(RegisterDevice):
    def __init__(self, who_am_i: int = 0x71):
        self.regs = bytearray(128)
        self.regs[WHO_AM_I] = who_am_i
        self.regs[PWR_MGMT_1] = 0x01
        self.accel = (0.0, 0.0, G)
        self.gyro = (0.0, 0.0, 0.0)
        self.temp_c = 25.0

    @property
    def bypass(self) -> bool:
        return bool(self.regs[INT_PIN_CFG] & 0x02)

    def _outputs(self) -> bytes:
        a_lsb = 16384 >> (self.regs[ACCEL_CONFIG] >> 3 & 3)
        g_lsb = 131.0 / (1 << (self.regs[GYRO_CONFIG] >> 3 & 3))
        accel = np.array(self.accel) / G * a_lsb
        gyro = np.degrees(np.array(self.gyro)) * g_lsb
        temp = (self.temp_c - 21.0) * 333.87
        return _be16(accel) + _be16([temp]) + _be16(gyro)

    def read(self, reg: int, n: int) -> bytes:
        regs = bytearray(self.regs)
        regs[ACCEL_XOUT_H:ACCEL_XOUT_H + 14] = self._outputs()
        return bytes(regs[(reg + i) % 128] for i in range(n))

    def write(self, reg: int, data: bytes) -> None:
        for i, b in enumerate(data):
            r = (reg + i) % 128
            if r != WHO_AM_I and not (ACCEL_XOUT_H <= r < ACCEL_XOUT_H + 14):
                self.regs[r] = b


class Ak8963Twin(RegisterDevice):
    WIA, ST1, HXL, ST2, CNTL1 = 0x00, 0x02, 0x03, 0x09, 0x0A
    UT_PER_LSB = 0.15  # 16-bit output

    def __init__(self, mpu: Mpu9250Twin):
        self.mpu = mpu
        self.cntl1 = 0
        self.field_ut = (20.0, 0.0, -40.0)
        self.st2_reads = 0

    def visible(self) -> bool:
        return self.present and self.mpu.bypass

    def read(self, reg: int, n: int) -> bytes:
        data = np.clip(np.round(np.array(self.field_ut) / self.UT_PER_LSB), -32760, 32760).astype("<i2").tobytes()
        regs = bytearray(16)
        regs[self.WIA] = 0x48
        regs[self.ST1] = 0x01 if self.cntl1 & 0x0F else 0x00
        regs[self.HXL:self.HXL + 6] = data
        regs[self.ST2] = 0x10 if self.cntl1 & 0x10 else 0x00
        regs[self.CNTL1] = self.cntl1
        out = bytes(regs[(reg + i) % 16] for i in range(n))
        if reg <= self.ST2 < reg + n:
            self.st2_reads += 1
        return out

    def write(self, reg: int, data: bytes) -> None:
        if reg == self.CNTL1 and data:
            self.cntl1 = data[0]
