"""An smbus2-compatible I2C bus with register-level device twins on it.

``I2cBusTwin`` offers the subset of ``smbus2.SMBus`` the drivers use, with smbus2's byte
conventions: ``read_word_data`` returns the *first* byte on the wire as the low byte (SMBus is
little-endian; big-endian chips like the INA226 therefore come back byte-swapped, as on the
robot). An address nobody answers raises ``OSError(EREMOTEIO)``, exactly what the kernel
returns on a NACK. A TCA9548A twin on the bus gates which devices behind it are visible; when
two selected channels hold devices at one address, reads are the wired-AND of both (an I2C
bus is open-drain), and ``max_selected`` remembers the most channels ever open at once.
"""
from __future__ import annotations

import errno
from typing import Iterable


def nack(address: int) -> OSError:
    return OSError(errno.EREMOTEIO, f"Remote I/O error (no ACK from 0x{address:02x})")


class RegisterDevice:
    """A device with a register pointer; subclasses implement ``read`` and ``write``."""

    present = True
    """False makes the device NACK (unplugged)."""

    def read(self, reg: int, n: int) -> bytes:  # pragma: no cover - interface
        raise NotImplementedError

    def write(self, reg: int, data: bytes) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def visible(self) -> bool:
        return self.present

    # devices without registers (the mux) override these
    def write_byte(self, value: int) -> None:
        self.pointer = value & 0xFF

    def read_byte(self) -> int:
        return self.read(getattr(self, "pointer", 0), 1)[0]


class Tca9548aTwin(RegisterDevice):
    """The TCA9548A mux: one control byte, bit n opens channel n; 0x00 at power-up."""

    def __init__(self) -> None:
        self.control = 0
        self.channels: dict[int, dict[int, RegisterDevice]] = {}
        self.max_selected = 0

    def attach(self, channel: int, address: int, device: RegisterDevice) -> RegisterDevice:
        self.channels.setdefault(channel, {})[address] = device
        return device

    def write_byte(self, value: int) -> None:
        self.control = value & 0xFF
        self.max_selected = max(self.max_selected, bin(self.control).count("1"))

    def read_byte(self) -> int:
        return self.control

    def read(self, reg: int, n: int) -> bytes:
        return bytes([self.control]) * n

    def write(self, reg: int, data: bytes) -> None:
        self.write_byte(reg)  # a block write's first byte is the control byte

    def behind(self, address: int) -> list[RegisterDevice]:
        return [devs[address] for ch, devs in sorted(self.channels.items())
                if self.control >> ch & 1 and address in devs and devs[address].visible()]


class I2cBusTwin:
    """An smbus2.SMBus look-alike; ``attach`` devices at addresses, then hand it to drivers."""

    def __init__(self) -> None:
        self.devices: dict[int, RegisterDevice] = {}
        self.transactions = 0

    def attach(self, address: int, device: RegisterDevice) -> RegisterDevice:
        self.devices[address] = device
        return device

    def _targets(self, address: int) -> list[RegisterDevice]:
        self.transactions += 1
        hits = []
        dev = self.devices.get(address)
        if dev is not None and dev.visible():
            hits.append(dev)
        for mux in self.devices.values():
            if isinstance(mux, Tca9548aTwin) and mux.visible():
                hits += mux.behind(address)
        if not hits:
            raise nack(address)
        return hits

    def _read(self, address: int, reg: int, n: int) -> bytes:
        out = None
        for dev in self._targets(address):
            data = dev.read(reg, n)
            out = data if out is None else bytes(a & b for a, b in zip(out, data))
        return out

    def _write(self, address: int, reg: int, data: Iterable[int]) -> None:
        payload = bytes(int(b) & 0xFF for b in data)
        for dev in self._targets(address):
            dev.write(reg, payload)

    # --- smbus2.SMBus API ---------------------------------------------------------------
    def write_byte(self, i2c_addr: int, value: int, force=None) -> None:
        for dev in self._targets(i2c_addr):
            dev.write_byte(value)

    def read_byte(self, i2c_addr: int, force=None) -> int:
        return self._targets(i2c_addr)[0].read_byte()

    def read_byte_data(self, i2c_addr: int, register: int, force=None) -> int:
        return self._read(i2c_addr, register, 1)[0]

    def write_byte_data(self, i2c_addr: int, register: int, value: int, force=None) -> None:
        self._write(i2c_addr, register, [value])

    def read_word_data(self, i2c_addr: int, register: int, force=None) -> int:
        lo, hi = self._read(i2c_addr, register, 2)
        return lo | hi << 8

    def write_word_data(self, i2c_addr: int, register: int, value: int, force=None) -> None:
        self._write(i2c_addr, register, [value & 0xFF, value >> 8 & 0xFF])

    def read_i2c_block_data(self, i2c_addr: int, register: int, length: int, force=None) -> list[int]:
        return list(self._read(i2c_addr, register, length))

    def write_i2c_block_data(self, i2c_addr: int, register: int, data, force=None) -> None:
        self._write(i2c_addr, register, data)

    def close(self) -> None:
        pass
