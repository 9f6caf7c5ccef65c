"""INA226 power monitor: calibration and voltage / current / power, the HAL's PowerMonitor.

Datasheet arithmetic (reference): current_lsb = max_expected_current / 32768;
CAL = round(0.00512 / (current_lsb * r_shunt)); the chip then computes
current = shunt * CAL / 2048 and power = current * bus / 20000, power LSB = 25 * current_lsb;
bus LSB 1.25 mV. Registers are big-endian and smbus2 words little-endian, so every word is
byte-swapped (a classic bug: reading 11.98 V as 28.7 V). The worked vector: 2 mOhm, 1 mA LSB
-> CAL 0x0A00; shunt 0x1F40 -> current 0x2710 (10 A); bus 0x2570 -> power 0x12B8 (119.82 W).

Vendor set-up: 0.010 ohm shunt, 8.3 A range, 256-sample averaging (seed power_watcher).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from hw.drivers.i2c import device_error, probe, s16, swap16
from hw.errors import InputError
from hw.interfaces import PowerReading

CONFIG, SHUNT, BUS, POWER, CURRENT, CALIBRATION = 0x00, 0x01, 0x02, 0x03, 0x04, 0x05
MANUFACTURER_ID, DIE_ID = 0xFE, 0xFF
TI = 0x5449
AVERAGING = (1, 4, 16, 64, 128, 256, 512, 1024)
CT_1100US = 0b100
MODE_CONTINUOUS = 0b111
BUS_LSB = 1.25e-3


def calibration(current_lsb: float, shunt_ohm: float) -> int:
    return round(0.00512 / (current_lsb * shunt_ohm))


def config_word(averaging: int) -> int:
    if averaging not in AVERAGING:
        raise ValueError(f"INA226 averaging must be one of {AVERAGING}, got {averaging}")
    return 0x4000 | AVERAGING.index(averaging) << 9 | CT_1100US << 6 | CT_1100US << 3 | MODE_CONTINUOUS


@dataclass(frozen=True)
class PowerSample:
    voltage: float
    current: float
    power: float


class Ina226:
    def __init__(self, bus, address: int = 0x40, shunt_ohm: float = 0.010, max_expected_current: float = 8.3,
                 averaging: int = 256, clock: Callable[[], float] = lambda: 0.0):
        self.bus, self.address = bus, address
        self.current_lsb = max_expected_current / 32768.0
        self.cal = calibration(self.current_lsb, shunt_ohm)
        self.config = config_word(averaging)
        self.clock = clock

    def read_word(self, reg: int) -> int:
        try:
            return swap16(self.bus.read_word_data(self.address, reg))
        except OSError as exc:
            raise device_error("INA226", self.address, exc) from None

    def write_word(self, reg: int, value: int) -> None:
        try:
            self.bus.write_word_data(self.address, reg, swap16(value))
        except OSError as exc:
            raise device_error("INA226", self.address, exc) from None

    def start(self) -> None:
        """Check it is an INA226 (TI manufacturer id), configure, calibrate."""
        probe(self.bus, self.address, "INA226 power monitor", MANUFACTURER_ID)
        mid = self.read_word(MANUFACTURER_ID)
        if mid != TI:
            raise InputError(f"INA226 power monitor at 0x{self.address:02x}: manufacturer id 0x{mid:04x}, "
                             f"expected 0x{TI:04x} (another chip at this address?)")
        self.write_word(CONFIG, self.config)
        self.write_word(CALIBRATION, self.cal)

    def sample(self) -> PowerSample:
        bus = self.read_word(BUS) * BUS_LSB
        current = s16(self.read_word(CURRENT)) * self.current_lsb
        power = self.read_word(POWER) * 25 * self.current_lsb
        return PowerSample(bus, current, power)

    def read(self) -> PowerReading:
        s = self.sample()
        return PowerReading(self.clock(), s.voltage, s.current)
