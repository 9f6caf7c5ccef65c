"""Register-level twin of the PCA9685 16-channel 12-bit PWM driver.

Models what the driver must get right (reference): PRE_SCALE only latches while MODE1.SLEEP is
set (writes while awake are ignored and counted in ``rejected_prescale_writes``); auto-increment
only with MODE1.AI; ALL_LED_* writes load every channel; full-on / full-off bits in ON_H / OFF_H
(full-off wins); outputs are off while asleep. ``duty(ch)`` is what the motor actually sees.
"""
from __future__ import annotations

from hw.emulators.i2c_bus import RegisterDevice

MODE1, MODE2, LED0, ALL_LED, PRE_SCALE = 0x00, 0x01, 0x06, 0xFA, 0xFE
RESTART, AI, SLEEP = 0x80, 0x20, 0x10


class Pca9685Twin(RegisterDevice):
    def __init__(self, oscillator_hz: float = 25e6):
        self.osc = oscillator_hz
        self.regs = bytearray(256)
        self.regs[MODE1] = SLEEP | 0x01  # power-up: asleep, ALLCALL
        self.regs[MODE2] = 0x04
        self.regs[PRE_SCALE] = 0x1E  # 200 Hz
        for ch in range(16):
            self.regs[LED0 + 4 * ch + 3] = 0x10  # full off
        self.rejected_prescale_writes = 0
        self.writes: list[tuple[int, bytes]] = []

    def _put(self, reg: int, value: int) -> None:
        if reg == PRE_SCALE:
            if not self.regs[MODE1] & SLEEP:
                self.rejected_prescale_writes += 1
                return
        if reg == MODE1:
            value &= ~RESTART & 0xFF  # writing RESTART restarts the PWM; it reads back as 0
        if ALL_LED <= reg <= ALL_LED + 3:
            for ch in range(16):
                self.regs[LED0 + 4 * ch + reg - ALL_LED] = value
        self.regs[reg] = value

    def write(self, reg: int, data: bytes) -> None:
        self.writes.append((reg, bytes(data)))
        for i, b in enumerate(data):
            self._put(reg + i if self.regs[MODE1] & AI else reg, b)

    def read(self, reg: int, n: int) -> bytes:
        step = 1 if self.regs[MODE1] & AI else 0
        return bytes(self.regs[(reg + i * step) & 0xFF] for i in range(n))

    # --- what the outputs do ------------------------------------------------------------
    @property
    def asleep(self) -> bool:
        return bool(self.regs[MODE1] & SLEEP)

    def frequency(self) -> float:
        return self.osc / (4096 * (self.regs[PRE_SCALE] + 1))

    def duty(self, ch: int) -> float:
        on_l, on_h, off_l, off_h = self.regs[LED0 + 4 * ch: LED0 + 4 * ch + 4]
        if self.asleep or off_h & 0x10:
            return 0.0
        if on_h & 0x10:
            return 1.0
        on, off = on_l | (on_h & 0x0F) << 8, off_l | (off_h & 0x0F) << 8
        return ((off - on) % 4096) / 4096.0

    def duties(self) -> list[float]:
        return [self.duty(ch) for ch in range(16)]
