"""TCA9548A I2C mux: one control byte selects channels (``write_byte(addr, 1 << ch)``).

All five AS5600 share 0x36 (reference), so exactly one channel may be open at a time; a
``select`` always writes a single bit. No register address: the control byte is the whole
transaction. 0x00 at power-up (nothing selected).
"""
from __future__ import annotations

from hw.drivers.i2c import device_error


class Tca9548a:
    def __init__(self, bus, address: int = 0x70):
        self.bus, self.address = bus, address
        self.selected: int | None = None

    def select(self, channel: int) -> None:
        if not 0 <= channel < 8:
            raise ValueError(f"TCA9548A channel {channel} out of 0..7")
        try:
            self.bus.write_byte(self.address, 1 << channel)
        except OSError as exc:
            self.selected = None
            raise device_error("TCA9548A mux", self.address, exc) from None
        self.selected = channel

    def release(self) -> None:
        try:
            self.bus.write_byte(self.address, 0)
        except OSError as exc:
            raise device_error("TCA9548A mux", self.address, exc) from None
        self.selected = None
