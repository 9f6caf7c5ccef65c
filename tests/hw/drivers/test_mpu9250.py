import math

import pytest

from hw.drivers.mpu9250 import Mpu9250
from hw.emulators.i2c_bus import I2cBusTwin
from hw.emulators.mpu9250 import Ak8963Twin, Mpu9250Twin
from hw.errors import InputError


def rig(who=0x71, accel=2, gyro=250):
    bus = I2cBusTwin()
    mpu = bus.attach(0x68, Mpu9250Twin(who))
    ak = bus.attach(0x0C, Ak8963Twin(mpu))
    return bus, mpu, ak, Mpu9250(bus, accel_range_g=accel, gyro_range_dps=gyro, clock=lambda: 1.25)


@pytest.mark.parametrize("accel,gyro", [(2, 250), (8, 1000), (16, 2000)])
def test_reads_accel_gyro_at_configured_scales(accel, gyro):
    bus, mpu, _, imu = rig(accel=accel, gyro=gyro)
    imu.start()
    assert mpu.regs[0x1C] >> 3 & 3 == (2, 4, 8, 16).index(accel)
    mpu.accel = (1.0, -2.0, 9.80665)
    mpu.gyro = (0.1, -0.2, 0.5)
    r = imu.read()
    assert r.stamp == 1.25
    assert r.accel == pytest.approx((1.0, -2.0, 9.80665), abs=9.81 * accel / 32768 * 2)
    assert r.gyro == pytest.approx((0.1, -0.2, 0.5), abs=math.radians(gyro / 32768 * 2))


def test_temperature_formula():
    _, mpu, _, imu = rig()
    imu.start()
    mpu.temp_c = 36.5
    assert imu.read_temperature() == pytest.approx(36.5, abs=0.01)


def test_magnetometer_through_bypass_reads_st2_after_data():
    bus, mpu, ak, imu = rig()
    with pytest.raises(OSError):
        bus.read_byte_data(0x0C, 0)  # hidden until bypass
    imu.start()
    assert imu.has_mag and ak.cntl1 == 0x16
    ak.field_ut = (30.0, -15.0, 45.0)
    assert imu.read_mag() == pytest.approx((30.0, -15.0, 45.0), abs=0.15)
    assert ak.st2_reads == 1


@pytest.mark.parametrize("who", [0x70, 0x73])
def test_board_variants_accepted(who):
    assert rig(who)[3].start() == who


def test_wrong_chip_id_is_input_error():
    with pytest.raises(InputError, match="WHO_AM_I 0x12"):
        rig(0x12)[3].start()
