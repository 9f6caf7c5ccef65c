"""`lupin hw ...` against the device emulators: human output, --json, and exit 2 on trouble."""
import json

import pytest

import lupin.cli.hw as hwc
from hw.drivers.led_strip import decode_spi
from hw.emulators.gpio import EmulatedLineRequest
from hw.emulators.hiwonder_bus import EmuServo, HiwonderBusEmulator
from hw.emulators.i2c_bus import I2cBusTwin, Tca9548aTwin
from hw.emulators.as5600 import As5600Twin
from hw.emulators.ina226 import Ina226Twin
from hw.emulators.mpu9250 import Ak8963Twin, Mpu9250Twin
from hw.emulators.pca9685 import Pca9685Twin
from hw.emulators.rplidar import RplidarEmulator
from lupin.cli import main


def run(capsys, *args):
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture
def servo_bus():
    with HiwonderBusEmulator({2: EmuServo(), 3: EmuServo()}) as emu:
        yield emu


@pytest.fixture
def i2c(monkeypatch):
    bus = I2cBusTwin()
    bus.attach(0x41, Pca9685Twin())
    ina = bus.attach(0x40, Ina226Twin(0.010))
    ina.set(13.05, 0.8)
    mpu = bus.attach(0x68, Mpu9250Twin())
    bus.attach(0x0C, Ak8963Twin(mpu))
    mux = bus.attach(0x70, Tca9548aTwin())
    for ch in range(5):
        mux.attach(ch, 0x36, As5600Twin(raw=1024 * (ch % 4)))
    monkeypatch.setattr(hwc, "open_i2c", lambda n: bus)
    return bus


def test_servo_read_human_and_json(capsys, servo_bus):
    servo_bus.servo(2).place(500)
    rc, out, _ = run(capsys, "hw", "servo", "read", "--port", servo_bus.path, "--id", "2")
    assert rc == 0 and "500 counts" in out and "12.00 V" in out
    rc, out, _ = run(capsys, "hw", "servo", "read", "--port", servo_bus.path, "--id", "2", "--json")
    data = json.loads(out)
    assert data["position_counts"] == 500 and data["vin_v"] == 12.0 and data["temperature_c"] == 36
    assert data["position_rad"] == pytest.approx(0.0, abs=1e-9)  # 500 counts = shoulder_pan home (12000 cdeg)


def test_servo_ping_move_offset(capsys, servo_bus):
    rc, out, _ = run(capsys, "hw", "servo", "ping", "--port", servo_bus.path, "--json")
    assert rc == 0 and json.loads(out)["servos"] == {"2": True, "3": True, "4": False, "5": False, "6": False}
    rc, out, _ = run(capsys, "hw", "servo", "move", "--port", servo_bus.path, "--id", "3", "--position", "640", "--time", "0")
    assert rc == 0
    rc, out, _ = run(capsys, "hw", "servo", "offset", "--port", servo_bus.path, "--id", "3", "--set", "-7", "--save", "--json")
    assert json.loads(out)["offset"] == -7 and servo_bus.servo(3).saved_offset == -7


def test_silent_servo_and_wrong_port_exit_2(capsys, servo_bus):
    rc, _, err = run(capsys, "hw", "servo", "read", "--port", servo_bus.path, "--id", "9")
    assert rc == 2 and err.count("\n") == 1 and "servo id 9" in err
    rc, _, err = run(capsys, "hw", "servo", "ping", "--port", servo_bus.path, "--id", "9")
    assert rc == 2 and "no servo answered" in err
    rc, _, err = run(capsys, "hw", "servo", "read", "--port", "/dev/ttyNOPE9", "--id", "2")
    assert rc == 2 and err.strip() == "lupin: Hiwonder servo bus port /dev/ttyNOPE9: cannot open (No such file or directory)"


def test_lidar_info_health_scan(capsys):
    with RplidarEmulator(points=250, rate_hz=20.0) as emu:
        rc, out, _ = run(capsys, "hw", "lidar", "info", "--port", emu.path, "--json")
        assert rc == 0 and json.loads(out)["model"] == 0x41
        rc, out, _ = run(capsys, "hw", "lidar", "health", "--port", emu.path)
        assert rc == 0 and "health good" in out
        rc, out, _ = run(capsys, "hw", "lidar", "scan", "--port", emu.path, "--revolutions", "2", "--json")
        data = json.loads(out)
        assert data["points_per_revolution"] == [250, 250]
        assert data["range_m"]["min"] == pytest.approx(1.5, abs=0.01) and data["range_m"]["max"] == pytest.approx(2.5, abs=0.05)
        emu.silent = True
        rc, _, err = run(capsys, "hw", "lidar", "health", "--port", emu.path)
        assert rc == 2 and "no reply to GET_HEALTH" in err


def test_i2c_scan_power_imu(capsys, i2c):
    rc, out, _ = run(capsys, "hw", "i2c-scan", "--json")
    data = json.loads(out)
    # the AK8963 (0x0C) sits behind the MPU9250 and is not on the bus until its bypass is set
    assert [d["address"] for d in data["devices"]] == [0x40, 0x41, 0x68, 0x70]
    assert data["joint_encoders"]["elbow"] == {"channel": 3, "degrees": 270.0, "magnet": "ok"}
    rc, out, _ = run(capsys, "hw", "power")
    assert rc == 0 and "13.050 V" in out and "battery 50 %" in out
    rc, out, _ = run(capsys, "hw", "imu", "--json")
    data = json.loads(out)
    assert data["who_am_i"] == 0x71 and data["accel"][2] == pytest.approx(9.807, abs=0.01) and data["mag_ut"]
    rc, out, _ = run(capsys, "hw", "i2c-scan", "--json")  # the IMU driver set the bypass: now it answers
    devices = json.loads(out)["devices"]
    assert [d["address"] for d in devices] == [0x0C, 0x40, 0x41, 0x68, 0x70]
    assert devices[0]["name"] == "AK8963 magnetometer"


def test_wrong_chip_and_missing_bus_exit_2(capsys, i2c, monkeypatch):
    i2c.devices[0x68].regs[0x75] = 0x55
    rc, _, err = run(capsys, "hw", "imu")
    assert rc == 2 and "WHO_AM_I 0x55" in err
    del i2c.devices[0x40]
    rc, _, err = run(capsys, "hw", "power")
    assert rc == 2 and "INA226 power monitor at 0x40: no answer" in err
    monkeypatch.setattr(hwc, "open_i2c", hwc.open_bus)
    rc, _, err = run(capsys, "hw", "power", "--bus", "97")
    assert rc == 2 and "/dev/i2c-97" in err


def test_encoders_estop_leds(capsys, monkeypatch, tmp_path):
    requests = {}

    def fake_request(chip, offsets, pull_up=True):
        req = EmulatedLineRequest(offsets)
        requests[tuple(offsets)] = req
        if len(offsets) > 1:
            req.levels[offsets[0]] = req.levels[offsets[1]] = 0
            req.turn(offsets[0], offsets[1], 44)  # someone turns front_left by hand
        else:
            req.set(offsets[0], 1)
        return req

    monkeypatch.setattr(hwc, "gpio_request", fake_request)
    rc, out, _ = run(capsys, "hw", "encoders", "--seconds", "0", "--json")
    wheels = json.loads(out)["wheels"]
    assert rc == 0 and wheels["front_left"] == {"ticks": 44, "lost": 0, "illegal": 0}
    assert wheels["rear_right"]["ticks"] == 0
    rc, out, _ = run(capsys, "hw", "estop")
    assert rc == 0 and "ENGAGED" in out
    dev = tmp_path / "spidev"
    dev.write_bytes(b"")
    monkeypatch.setenv("LUPIN_HW__DEVICES__LEDS__DEVICE", str(dev))
    rc, out, _ = run(capsys, "hw", "leds", "--state", "estop", "--json")
    assert rc == 0 and json.loads(out)["wire"] == "00ff00"  # red in BRG: blue 0, red 255, green 0
    assert decode_spi(dev.read_bytes())[:3] == bytes([0, 255, 0])
    rc, _, err = run(capsys, "hw", "leds", "--state", "purple")
    assert rc == 2 and "unknown" in err
