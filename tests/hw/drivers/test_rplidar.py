import time

import numpy as np
import pytest

from hw.drivers.rplidar import RplidarC1
from hw.drivers.rplidar_protocol import Req
from hw.emulators.rplidar import RplidarEmulator
from hw.errors import InputError
from hw.interfaces import DeviceError


@pytest.fixture
def lidar():
    with RplidarEmulator(points=300, rate_hz=20.0) as emu:
        drv = RplidarC1.open(emu.path, spinup_s=1.0, timeout_s=0.3)
        try:
            yield emu, drv
        finally:
            drv.close()


def test_info_and_health(lidar):
    emu, drv = lidar
    info = drv.info()
    assert info.model == 0x41 and info.firmware == "1.01"
    assert drv.health() == ("good", 0)
    emu.health = 2
    assert drv.health()[0] == "error"


def test_scan_matches_the_scene(lidar):
    emu, drv = lidar
    drv.start()
    scan = drv.wait_for_scan(2.0)
    assert scan is not None
    assert scan.angles.size == 300
    # the box room: 2 m ahead (lidar 0 deg), 1.5 m to each side
    assert scan.ranges[0] == pytest.approx(2.0, abs=0.002)
    side = np.argmin(np.abs(scan.angles - np.pi / 2))
    assert scan.ranges[side] == pytest.approx(1.5, abs=0.002)
    assert drv.latest_scan() is scan or drv.latest_scan().stamp >= scan.stamp


def test_spinup_silence_is_waited_out_and_garbage_resynchronised():
    with RplidarEmulator(points=200, rate_hz=20.0, spinup_s=0.3) as emu:
        drv = RplidarC1.open(emu.path, spinup_s=1.0, timeout_s=0.3)
        drv.start()  # returns only once the descriptor arrived after the spin-up
        assert drv.wait_for_scan(2.0) is not None
        n = drv.parser.revolutions
        emu.inject(bytes([0x13, 0xFF, 0x00, 0x42, 0x99, 0x01, 0x7E]))
        emu.drop(3)
        end = time.monotonic() + 2.0
        while drv.parser.revolutions < n + 4 and time.monotonic() < end:
            time.sleep(0.02)
        assert drv.parser.resyncs >= 1
        assert drv.latest_scan().angles.size == 200  # whole revolutions again
        drv.close()
        end = time.monotonic() + 2.0  # the emulator's reader thread takes the byte in its own time
        while emu.requests[-1] != Req.STOP and time.monotonic() < end:
            time.sleep(0.01)
        assert emu.requests[-1] == Req.STOP  # stop on exit


def test_silent_lidar_is_a_device_error_and_a_dropout_is_none():
    with RplidarEmulator(points=100, rate_hz=20.0) as emu:
        drv = RplidarC1.open(emu.path, spinup_s=0.2, timeout_s=0.1, stale_s=0.2)
        drv.start()
        assert drv.wait_for_scan(1.0) is not None
        emu.silent = True
        time.sleep(0.35)
        assert drv.latest_scan() is None  # stale: a dropout, not an exception
        with pytest.raises(DeviceError, match="GET_HEALTH"):
            drv.health()
        drv.close()


def test_wrong_port_is_input_error():
    with pytest.raises(InputError, match="RPLidar port /dev/nope"):
        RplidarC1.open("/dev/nope")
