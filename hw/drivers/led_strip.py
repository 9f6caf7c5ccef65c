"""The WS2812-style status strip on an SPI data line: the HAL's LedStrip.

``write`` takes the bytes exactly as they go out on the data line: the colour-order remap
(Mirte-247264's strip is BRG, seed) already happened at ``hw.leds.to_wire``, the one chokepoint;
this driver never reorders. A WS2812 bit is a 1.25 us pulse whose high time says 0 or 1; at an
SPI clock of 2.4 MHz three SPI bits make one WS2812 bit (0 -> 100, 1 -> 110), so each wire byte
becomes three SPI bytes, followed by > 280 us of low as the latch. Encoding is vectorised.
"""
from __future__ import annotations

import fcntl
import os
import stat
import struct

import numpy as np

from hw.errors import InputError
from hw.interfaces import DeviceError

SPI_IOC_WR_MAX_SPEED_HZ = 0x40046B04
LATCH_BYTES = 90  # 90 * 8 / 2.4 MHz = 300 us low


def encode_spi(wire: bytes) -> bytes:
    bits = np.unpackbits(np.frombuffer(wire, dtype=np.uint8))
    triples = np.empty((bits.size, 3), dtype=np.uint8)
    triples[:, 0] = 1
    triples[:, 1] = bits
    triples[:, 2] = 0
    return np.packbits(triples.ravel()).tobytes() + bytes(LATCH_BYTES)


def decode_spi(spi: bytes) -> bytes:
    """The inverse, for tests and diagnostics: the wire bytes an SPI stream carries."""
    body = spi[:len(spi) - LATCH_BYTES]
    bits = np.unpackbits(np.frombuffer(body, dtype=np.uint8)).reshape(-1, 3)
    if not (np.all(bits[:, 0] == 1) and np.all(bits[:, 2] == 0)):
        raise ValueError("not a WS2812 SPI stream")
    return np.packbits(bits[:, 1]).tobytes()


class SpiLedStrip:
    def __init__(self, device: str, num_leds: int, spi_hz: int = 2_400_000):
        self.device, self.num_leds = device, num_leds
        try:
            self.fd = os.open(device, os.O_WRONLY)
        except OSError as exc:
            raise InputError(f"LED strip SPI device {device}: cannot open ({exc.strerror})") from None
        if stat.S_ISCHR(os.fstat(self.fd).st_mode):
            try:
                fcntl.ioctl(self.fd, SPI_IOC_WR_MAX_SPEED_HZ, struct.pack("<I", spi_hz))
            except OSError as exc:
                raise InputError(f"LED strip SPI device {device}: cannot set {spi_hz} Hz ({exc.strerror})") from None

    def write(self, wire: bytes) -> None:
        if len(wire) != 3 * self.num_leds:
            raise ValueError(f"LED strip: expected {3 * self.num_leds} wire bytes, got {len(wire)}")
        try:
            os.write(self.fd, encode_spi(wire))
        except OSError as exc:
            raise DeviceError(f"LED strip {self.device}: {exc.strerror}") from None

    def close(self) -> None:
        os.close(self.fd)
