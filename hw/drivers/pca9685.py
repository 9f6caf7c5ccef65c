"""PCA9685 16-channel 12-bit PWM driver (the motor PWM at 0x41, seed).

Frequency (reference): prescale = round(osc / (4096 f)) - 1, clamped 3..255 (Adafruit's driver
omits the -1: a known discrepancy, not repeated here). PRE_SCALE only latches while asleep, so
the sequence is: SLEEP, write prescale, restore MODE1, wait >= 500 us for the oscillator, then
RESTART | AI. Duty maps linearly onto 0..4095 counts; 0 and 1 use the full-off / full-on bits
so a stopped motor gets no glitch pulses. ``all_off`` writes ALL_LED_OFF_H full-off: every
output, wheels or not, in one transaction (the e-stop path).

``sleep`` is injected (the backend passes ``time.sleep``): this is the only wait in the driver.
"""
from __future__ import annotations

from typing import Callable

from hw.drivers.i2c import device_error, probe

MODE1, MODE2, LED0_ON_L, ALL_LED_ON_L, ALL_LED_OFF_H, PRE_SCALE = 0x00, 0x01, 0x06, 0xFA, 0xFD, 0xFE
RESTART, AI, SLEEP, ALLCALL = 0x80, 0x20, 0x10, 0x01
OUTDRV = 0x04
FULL = 0x10
OSC_SETTLE_S = 0.0005


def prescale_for(frequency_hz: float, oscillator_hz: float = 25e6) -> int:
    return max(3, min(255, round(oscillator_hz / (4096.0 * frequency_hz)) - 1))


def channel_bytes(duty: float) -> list[int]:
    """[ON_L, ON_H, OFF_L, OFF_H] for a duty in [0, 1]."""
    if not duty > 0.0:  # also NaN
        return [0, 0, 0, FULL]
    if duty >= 1.0:
        return [0, FULL, 0, 0]
    off = round(duty * 4095)
    return [0, 0, off & 0xFF, off >> 8]


class Pca9685:
    def __init__(self, bus, address: int = 0x41, oscillator_hz: float = 25e6,
                 sleep: Callable[[float], None] | None = None):
        self.bus, self.address, self.oscillator_hz = bus, address, oscillator_hz
        self._sleep = sleep or (lambda s: None)

    def start(self, frequency_hz: float) -> None:
        """Probe, totem-pole outputs, everything off, then the frequency sequence."""
        probe(self.bus, self.address, "PCA9685 motor PWM", MODE1)
        try:
            self.bus.write_byte_data(self.address, MODE2, OUTDRV)
            self.bus.write_byte_data(self.address, MODE1, AI | ALLCALL)
        except OSError as exc:
            raise device_error("PCA9685", self.address, exc) from None
        self.all_off()
        self.set_frequency(frequency_hz)

    def set_frequency(self, frequency_hz: float) -> int:
        prescale = prescale_for(frequency_hz, self.oscillator_hz)
        a = self.address
        try:
            old = self.bus.read_byte_data(a, MODE1) & ~RESTART & 0xFF
            self.bus.write_byte_data(a, MODE1, old | SLEEP)
            self.bus.write_byte_data(a, PRE_SCALE, prescale)
            self.bus.write_byte_data(a, MODE1, old & ~SLEEP & 0xFF)
            self._sleep(OSC_SETTLE_S)
            self.bus.write_byte_data(a, MODE1, (old & ~SLEEP & 0xFF) | RESTART | AI)
        except OSError as exc:
            raise device_error("PCA9685", a, exc) from None
        return prescale

    def set_duty(self, channel: int, duty: float) -> None:
        if not 0 <= channel < 16:
            raise ValueError(f"PCA9685 channel {channel} out of 0..15")
        try:
            self.bus.write_i2c_block_data(self.address, LED0_ON_L + 4 * channel, channel_bytes(duty))
        except OSError as exc:
            raise device_error("PCA9685", self.address, exc) from None

    def all_off(self) -> None:
        try:
            self.bus.write_byte_data(self.address, ALL_LED_OFF_H, FULL)
        except OSError as exc:
            raise device_error("PCA9685", self.address, exc) from None
