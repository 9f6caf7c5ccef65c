"""Register-level twin of the AS5600 magnetic absolute encoder (put it behind a Tca9548aTwin).

12-bit angles big-endian in RAW_ANGLE / ANGLE, STATUS magnet bits (MD detected, ML too weak,
MH too strong), AGC and MAGNITUDE. A write to BURN (0xFF) is recorded in ``burned``: the
driver must never do it (it permanently programs the chip).
"""
from __future__ import annotations

from hw.emulators.i2c_bus import RegisterDevice

STATUS, RAW_ANGLE, ANGLE, AGC, MAGNITUDE, BURN = 0x0B, 0x0C, 0x0E, 0x1A, 0x1B, 0xFF
MH, ML, MD = 0x08, 0x10, 0x20


class As5600Twin(RegisterDevice):
    def __init__(self, raw: int = 0, magnet: str = "ok"):
        self.raw = raw
        self.magnet = magnet  # "ok", "weak", "strong" or "none"
        self.burned = False
        self.regs = bytearray(256)

    def _regs(self) -> bytearray:
        r = bytearray(self.regs)
        status = {"ok": MD, "weak": MD | ML, "strong": MD | MH, "none": ML}[self.magnet]
        raw = self.raw & 0x0FFF
        r[STATUS] = status
        r[RAW_ANGLE], r[RAW_ANGLE + 1] = raw >> 8, raw & 0xFF
        r[ANGLE], r[ANGLE + 1] = raw >> 8, raw & 0xFF
        r[AGC] = {"ok": 128, "weak": 255, "strong": 0, "none": 255}[self.magnet]
        r[MAGNITUDE], r[MAGNITUDE + 1] = 0x06, 0x00
        return r

    def read(self, reg: int, n: int) -> bytes:
        r = self._regs()
        return bytes(r[(reg + i) & 0xFF] for i in range(n))

    def write(self, reg: int, data: bytes) -> None:
        if reg == BURN:
            self.burned = True
        for i, b in enumerate(data):
            self.regs[(reg + i) & 0xFF] = b
