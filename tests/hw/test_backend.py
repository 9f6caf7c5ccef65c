"""The whole stack on the hardware backend over device emulators, on the wall clock (no MuJoCo)."""
import logging
import time
from contextlib import ExitStack

import pytest

from arm.presets import ARM_JOINTS
from hw.backend import HwBackend
from hw.drivers.hiwonder_protocol import Cmd
from hw.drivers.led_strip import decode_spi
from hw.errors import InputError
from hw.interfaces import Twist
from hw.leds import PALETTE, to_wire
from mission.runtime.config import LupinConfig
from mission.runtime.robot import build_robot
from tests.hw.emulated import emulated_robot

FORWARD_A = {"front_left": 2, "front_right": 1, "rear_left": 6, "rear_right": 5}
REVERSE_B = {"front_left": 3, "front_right": 0, "rear_left": 7, "rear_right": 4}


@pytest.fixture
def stack():
    with ExitStack() as s:
        yield s


def test_full_stack_on_emulated_hardware(stack, tmp_path, caplog):
    emu = emulated_robot(stack, tmp_path)
    with caplog.at_level(logging.WARNING, logger="hw.backend"):
        backend = stack.enter_context(HwBackend(emu.config, **emu.boundaries()))
    assert any("E-STOP POLARITY ASSUMED" in r.getMessage() for r in caplog.records), "the robot must warn of the pin"
    hal = backend.hal
    robot = build_robot(LupinConfig(hw=emu.config), hal)
    robot.start()
    robot.scheduler.every("teleop", 10.0, lambda now: robot.mux.publish("manual", Twist(vx=0.2), now))
    robot.scheduler.run_for(0.3)  # the arm pins the live pose (every servo at 500 counts)
    goal = dict(zip(ARM_JOINTS, robot.arm.preset("inspect")))
    robot.scheduler.run_for(1.0)

    # drive command -> PWM registers: every wheel forward on its A channel, B at zero
    duties = emu.pwm.duties()
    assert all(duties[ch] > 0.05 for ch in FORWARD_A.values()), duties
    assert all(duties[ch] == 0.0 for ch in REVERSE_B.values()), duties
    assert abs(emu.pwm.frequency() - emu.config.devices.pwm.frequency_hz) < 2

    # servo preset -> bus packets: the trajectory's samples go out, heading for the goal
    servos = emu.config.servos
    for joint in ("shoulder_lift", "elbow", "wrist"):
        target = round(servos.rad_to_counts(servos.joints[joint], goal[joint]))
        sent = [int.from_bytes(f.params[:2], "little") for f in emu.servo_bus.frames
                if f.cmd == Cmd.MOVE_TIME_WRITE and f.servo_id == servos.joints[joint].id]
        assert sent and abs(sent[-1] - target) < abs(500 - target) - 10, (joint, sent, target)

    # lidar bytes -> scans: the emulated 4 m x 3 m room
    scan = hal.lidar.latest_scan()
    assert scan is not None and scan.angles.size == 200
    assert scan.ranges[0] == pytest.approx(2.0, abs=0.01)

    # power and IMU from the register twins, LEDs in BRG wire order
    assert hal.power.read().voltage == pytest.approx(12.4, abs=0.01)
    assert hal.imu.read().accel[2] == pytest.approx(9.81, abs=0.01)
    assert decode_spi(open(emu.led_path, "rb").read()[-(3 * 3 * 8 + 90):]) == to_wire([PALETTE["driving"]] * 8, "BRG")

    # the e-stop pin: every PCA9685 output off on the next control tick
    emu.line_request(emu.config.devices.estop.line).set(emu.config.devices.estop.line, 1)
    robot.scheduler.run_for(0.2)
    assert emu.pwm.duties() == [0.0] * 16
    assert robot.estop.state is True


def test_close_stops_the_lidar_and_turns_the_motors_off(stack, tmp_path):
    emu = emulated_robot(stack, tmp_path)
    backend = HwBackend(emu.config, **emu.boundaries())
    backend.hal.wheels.set_duties([0.5, 0.5, 0.5, 0.5])
    backend.close()
    end = time.monotonic() + 1.0
    while emu.lidar.requests[-1] != 0x25 and time.monotonic() < end:
        time.sleep(0.005)
    assert emu.lidar.requests[-1] == 0x25  # STOP
    assert emu.pwm.duties() == [0.0] * 16
    assert not backend.watchdog._thread.is_alive()  # its watch ends with it


def test_wheels_left_turning_by_a_stalled_loop_are_cut_on_the_robot(stack, tmp_path):
    """``hw.wheel_watchdog`` on the assembled backend: a write, then silence (no control loop
    runs here), and within the configured limit every motor output is off."""
    emu = emulated_robot(stack, tmp_path)
    backend = stack.enter_context(HwBackend(emu.config, **emu.boundaries()))
    backend.hal.wheels.set_duties([0.5, 0.5, 0.5, 0.5])
    assert max(emu.pwm.duties()) > 0.4
    end = time.monotonic() + 10.0
    while max(emu.pwm.duties()) > 0.0 and time.monotonic() < end:
        time.sleep(0.02)
    assert emu.pwm.duties() == [0.0] * 16 and backend.watchdog.cuts == 1


@pytest.mark.parametrize("breakage, message", [
    (lambda emu: setattr(emu.pwm, "present", False), "PCA9685 motor PWM at 0x41"),
    (lambda emu: emu.imu.regs.__setitem__(0x75, 0x12), "WHO_AM_I 0x12"),
    (lambda emu: emu.servo_bus.servos.pop(4), r"no answer from elbow \(id 4\)"),
    (lambda emu: emu.config.devices.lidar.__setattr__("port", "/dev/ttyNOPE"), "RPLidar port /dev/ttyNOPE"),
    (lambda emu: setattr(emu.lidar, "silent", True), "RPLidar on"),
    (lambda emu: emu.config.devices.cameras["wrist"].__setattr__("device", "/nonexistent/video7"), "camera wrist"),
])
def test_missing_device_at_start_up_is_one_clear_input_error(stack, tmp_path, breakage, message):
    emu = emulated_robot(stack, tmp_path)
    breakage(emu)
    with pytest.raises(InputError, match=message) as err:
        HwBackend(emu.config, **emu.boundaries())
    assert "\n" not in str(err.value)
