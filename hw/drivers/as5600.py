"""AS5600 magnetic absolute encoders, one per arm joint, behind the TCA9548A mux.

Reference: 0x36 on every channel; STATUS 0x0B (MD 0x20 magnet detected, ML 0x10 too weak,
MH 0x08 too strong); ANGLE 0x0E-0x0F 12-bit big-endian, mask 0x0FFF, deg = raw * 360 / 4096.
Never write BURN 0xFF (this driver never writes at all). Each read selects the joint's channel
first, so two sensors are never on the bus together.
"""
from __future__ import annotations

from dataclasses import dataclass

from hw.drivers.i2c import device_error
from hw.drivers.tca9548a import Tca9548a

STATUS, RAW_ANGLE, ANGLE = 0x0B, 0x0C, 0x0E
MH, ML, MD = 0x08, 0x10, 0x20


@dataclass(frozen=True)
class JointAngle:
    raw: int
    degrees: float
    magnet: str  # "ok", "too weak", "too strong", "not detected"


def magnet_status(status: int) -> str:
    if not status & MD:
        return "not detected"
    if status & ML:
        return "too weak"
    if status & MH:
        return "too strong"
    return "ok"


class As5600Array:
    def __init__(self, bus, mux: Tca9548a, channels: dict[str, int], address: int = 0x36):
        self.bus, self.mux, self.channels, self.address = bus, mux, dict(channels), address

    def read(self, joint: str) -> JointAngle:
        self.mux.select(self.channels[joint])
        try:
            status = self.bus.read_byte_data(self.address, STATUS)
            hi, lo = self.bus.read_i2c_block_data(self.address, ANGLE, 2)
        except OSError as exc:
            raise device_error(f"AS5600 ({joint}, mux channel {self.channels[joint]})", self.address, exc) from None
        raw = (hi << 8 | lo) & 0x0FFF
        return JointAngle(raw, raw * 360.0 / 4096.0, magnet_status(status))

    def read_all(self) -> dict[str, JointAngle]:
        return {joint: self.read(joint) for joint in self.channels}
