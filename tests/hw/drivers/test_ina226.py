import pytest

from hw.devices_config import Ina226Config
from hw.drivers.ina226 import Ina226, calibration, config_word
from hw.power_policy import PowerPolicy
from hw.emulators.i2c_bus import I2cBusTwin
from hw.emulators.ina226 import Ina226Twin
from hw.errors import InputError
from hw.interfaces import PowerReading


def test_reference_test_vector():
    # 2 mOhm shunt, 1 mA LSB -> CAL 0x0A00; shunt 0x1F40 -> 10 A; bus 0x2570 -> power 0x12B8
    assert calibration(0.001, 0.002) == 0x0A00
    bus = I2cBusTwin()
    twin = bus.attach(0x40, Ina226Twin(shunt_ohm=0.002))
    ina = Ina226(bus, 0x40, shunt_ohm=0.002, max_expected_current=0.001 * 32768)
    ina.start()
    assert twin.regs[0x05] == 0x0A00
    twin.shunt_raw, twin.bus_raw = 0x1F40, 0x2570
    assert twin.current_register() == 0x2710
    assert ina.read_word(0x03) == 0x12B8
    s = ina.sample()
    assert s.current == pytest.approx(10.0)
    assert s.voltage == pytest.approx(11.98)
    assert s.power == pytest.approx(119.8, abs=0.05)


def test_bytes_are_swapped_big_endian():
    bus = I2cBusTwin()
    bus.attach(0x40, Ina226Twin())
    assert bus.read_word_data(0x40, 0xFE) == 0x4954  # what smbus2 hands back, little-endian
    assert Ina226(bus).read_word(0xFE) == 0x5449


def test_vendor_setup_reads_pack_voltage_and_current():
    bus = I2cBusTwin()
    twin = bus.attach(0x40, Ina226Twin(shunt_ohm=0.010))
    ina = Ina226(bus, clock=lambda: 4.5)
    ina.start()
    assert twin.regs[0x00] == config_word(256)
    twin.set(12.6, 2.5)
    r = ina.read()
    assert r.stamp == 4.5
    assert r.voltage == pytest.approx(12.6, abs=2e-3)
    assert r.current == pytest.approx(2.5, abs=0.01)
    twin.set(12.6, -1.0)
    assert ina.read().current == pytest.approx(-1.0, abs=0.01)


def test_wrong_chip_id_is_input_error():
    bus = I2cBusTwin()
    bus.attach(0x40, Ina226Twin(manufacturer_id=0x1234))
    with pytest.raises(InputError, match="manufacturer id 0x1234"):
        Ina226(bus).start()


def test_policy_percentage_low_and_turn_off():
    p = PowerPolicy(Ina226Config())
    assert p.update(0, PowerReading(0, 15.0, 1)).percentage == 100.0
    assert p.update(0, PowerReading(0, 13.05, 1)).percentage == pytest.approx(50.0)
    s = p.update(1.0, PowerReading(1, 11.0, 1))
    assert s.percentage == 0.0 and not s.low
    assert not p.update(20.9, PowerReading(20.9, 11.0, 1)).low
    s = p.update(21.0, PowerReading(21, 10.9, 1))
    assert s.low and not s.turn_off
    assert not p.update(30.9, PowerReading(30.9, 10.9, 1)).turn_off
    assert p.update(31.0, PowerReading(31, 10.9, 1)).turn_off


def test_policy_sag_that_recovers_resets_and_garbage_is_ignored():
    p = PowerPolicy(Ina226Config())
    p.update(0, PowerReading(0, 11.0, 1))
    p.update(15, PowerReading(15, 12.0, 1))  # recovered
    assert not p.update(25, PowerReading(25, 11.0, 1)).low
    before = p.state
    assert p.update(26, PowerReading(26, float("nan"), 1)) == before
    assert not p.update(44, PowerReading(44, 11.0, 1)).low
    assert p.update(45, PowerReading(45, 11.0, 1)).low
    assert p.update(46, PowerReading(46, 11.0, 6.0)).over_current
