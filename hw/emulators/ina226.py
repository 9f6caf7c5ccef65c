"""Register-level twin of the INA226 power monitor.

16-bit registers, big-endian on the wire (so smbus2's ``read_word_data`` sees them swapped).
The shunt and bus registers follow from the physical state (``set``); CURRENT and POWER are
computed by the chip from the calibration register exactly as the datasheet says:
current = shunt * CAL / 2048, power = current * bus / 20000. Writing CONFIG bit 15 resets.
"""
from __future__ import annotations

from hw.emulators.i2c_bus import RegisterDevice

CONFIG, SHUNT, BUS, POWER, CURRENT, CALIBRATION, MASK_ENABLE, ALERT = range(8)
MANUFACTURER_ID, DIE_ID = 0xFE, 0xFF


def _s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


class Ina226Twin(RegisterDevice):
    def __init__(self, shunt_ohm: float = 0.010, manufacturer_id: int = 0x5449):
        self.shunt_ohm = shunt_ohm
        self.manufacturer_id = manufacturer_id
        self.regs: dict[int, int] = {}
        self._reset()
        self.shunt_raw = 0
        self.bus_raw = 0

    def _reset(self) -> None:
        self.regs = {CONFIG: 0x4127, CALIBRATION: 0, MASK_ENABLE: 0, ALERT: 0}

    def set(self, voltage: float, current: float) -> None:
        """The physical state: pack voltage (V) and current through the shunt (A)."""
        self.bus_raw = max(0, min(0x7FFF, round(voltage / 1.25e-3)))
        self.shunt_raw = max(-0x8000, min(0x7FFF, round(current * self.shunt_ohm / 2.5e-6)))

    def _value(self, reg: int) -> int:
        if reg == SHUNT:
            return self.shunt_raw & 0xFFFF
        if reg == BUS:
            return self.bus_raw
        current = int(self.shunt_raw * self.regs[CALIBRATION] / 2048)
        if reg == CURRENT:
            return max(-0x8000, min(0x7FFF, current)) & 0xFFFF
        if reg == POWER:
            return min(0xFFFF, abs(current) * self.bus_raw // 20000)
        if reg == MANUFACTURER_ID:
            return self.manufacturer_id
        if reg == DIE_ID:
            return 0x2260
        return self.regs.get(reg, 0)

    def read(self, reg: int, n: int) -> bytes:
        v = self._value(reg)
        return bytes([v >> 8 & 0xFF, v & 0xFF] * ((n + 1) // 2))[:n]

    def write(self, reg: int, data: bytes) -> None:
        if len(data) < 2 or reg not in (CONFIG, CALIBRATION, MASK_ENABLE, ALERT):
            return  # pointer-only or read-only: ignored, like the chip
        value = data[0] << 8 | data[1]
        if reg == CONFIG and value & 0x8000:
            self._reset()
            return
        self.regs[reg] = value & (0x7FFF if reg == CALIBRATION else 0xFFFF)

    def current_register(self) -> int:
        return _s16(self._value(CURRENT))
