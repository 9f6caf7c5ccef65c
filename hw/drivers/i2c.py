"""Opening the I2C bus and the two things every I2C driver needs: a clear error, 16-bit words.

``open_bus(n)`` is the real boundary (``smbus2.SMBus(n)``, imported lazily); tests pass an
``hw.emulators.i2c_bus.I2cBusTwin`` to the drivers instead. A bus that does not exist is bad
input (InputError naming /dev/i2c-N); a device that does not ACK at start-up is too
(``probe``), while a NACK in the running loop is a ``DeviceError`` the caller degrades on.
"""
from __future__ import annotations

from hw.errors import InputError
from hw.interfaces import DeviceError


def open_bus(number: int):
    """``smbus2.SMBus(number)``, or InputError naming the device file."""
    import smbus2

    try:
        return smbus2.SMBus(number)
    except (FileNotFoundError, PermissionError, OSError) as exc:
        raise InputError(f"I2C bus /dev/i2c-{number}: cannot open ({exc.strerror or exc})") from None


def probe(bus, address: int, what: str, register: int = 0x00) -> int:
    """Read one byte at start-up; a silent address is one clear InputError naming the device."""
    try:
        return bus.read_byte_data(address, register)
    except OSError:
        raise InputError(f"{what} at 0x{address:02x}: no answer on the I2C bus (wiring, address or power)") from None


def device_error(what: str, address: int, exc: OSError) -> DeviceError:
    return DeviceError(f"{what} at 0x{address:02x}: {exc.strerror or exc}")


def swap16(v: int) -> int:
    """smbus2 words are little-endian on the wire; big-endian chips need their bytes swapped."""
    return (v & 0xFF) << 8 | v >> 8 & 0xFF


def s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v
