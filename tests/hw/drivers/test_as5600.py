import pytest

from hw.drivers.as5600 import As5600Array
from hw.drivers.tca9548a import Tca9548a
from hw.emulators.as5600 import As5600Twin
from hw.emulators.i2c_bus import I2cBusTwin, Tca9548aTwin
from hw.interfaces import DeviceError

CHANNELS = {"gripper": 0, "shoulder_pan": 1, "shoulder_lift": 2, "elbow": 3, "wrist": 4}


def rig():
    bus = I2cBusTwin()
    mux = bus.attach(0x70, Tca9548aTwin())
    twins = {j: mux.attach(ch, 0x36, As5600Twin(raw=100 * (ch + 1))) for j, ch in CHANNELS.items()}
    return bus, mux, twins, As5600Array(bus, Tca9548a(bus, 0x70), CHANNELS)


def test_each_joint_read_on_its_own_channel():
    _, mux, twins, enc = rig()
    twins["elbow"].raw = 2048
    angles = enc.read_all()
    assert angles["elbow"].raw == 2048 and angles["elbow"].degrees == pytest.approx(180.0)
    assert angles["gripper"].raw == 100 and angles["wrist"].raw == 500
    assert mux.max_selected == 1  # never two sensors at 0x36 at once
    assert not any(t.burned for t in twins.values())


def test_magnet_status():
    _, _, twins, enc = rig()
    twins["wrist"].magnet = "weak"
    twins["elbow"].magnet = "strong"
    twins["gripper"].magnet = "none"
    assert enc.read("wrist").magnet == "too weak"
    assert enc.read("elbow").magnet == "too strong"
    assert enc.read("gripper").magnet == "not detected"
    assert enc.read("shoulder_pan").magnet == "ok"


def test_twin_shows_wired_and_when_two_channels_are_open():
    bus, mux, twins, _ = rig()
    bus.write_byte(0x70, 0b11)
    assert bus.read_byte_data(0x36, 0x0F) == (100 & 200)  # why the driver opens one at a time


def test_missing_sensor_is_device_error_naming_the_joint():
    _, _, twins, enc = rig()
    twins["elbow"].present = False
    with pytest.raises(DeviceError, match="elbow"):
        enc.read("elbow")
