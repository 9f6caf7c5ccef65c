"""The base chain on fake devices: encoders -> odometry, mux -> IK -> PID -> duties."""
import math

import numpy as np
import pytest

from hw.base_controller import STOPPED_ENCODER_FAULT, STOPPED_ESTOP, STOPPED_INACTIVE
from hw.config import BaseConfig, HwConfig
from hw.controller_manager import ControllerState
from hw.interfaces import Twist
from tests.fixtures import make_base_rig, quiet_logger

FWD = Twist(0.255, 0.0, 0.0)  # 5 rad/s on every wheel


def drive(rig, twist, seconds, source="auto"):
    """Publish ``twist`` at 10 Hz (offset from the control beat) while running the scheduler."""
    t0 = rig.clock.now()
    for k in range(int(round(seconds * 10))):
        t = t0 + k * 0.1 + 0.05
        rig.scheduler.run_until(t)
        rig.mux.publish(source, twist, t)
    rig.scheduler.run_until(t0 + seconds)


def test_tracks_forward_command_and_odometry_follows():
    rig = make_base_rig(log=quiet_logger())
    drive(rig, FWD, 3.0)
    np.testing.assert_allclose(rig.base.wheel_speeds, 5.0, rtol=0.03)
    assert rig.base.source == "auto" and rig.base.command == FWD
    pose = rig.base.odometry.pose
    # x equals the wheel angle travelled times the radius (the plant's ground truth)
    truth = rig.plant.encoders.ticks[0] / 1320 * 2 * math.pi * 0.051
    assert pose.x == pytest.approx(truth, rel=1e-3)
    assert abs(pose.y) < 1e-9 and abs(pose.yaw) < 1e-9
    assert 0.6 < pose.x < 0.255 * 3.0


def test_strafe_moves_odometry_sideways():
    rig = make_base_rig(log=quiet_logger())
    drive(rig, Twist(0.0, 0.2, 0.0), 2.0, source="manual")
    pose = rig.base.odometry.pose
    assert pose.y > 0.25 and abs(pose.x) < 0.01 and abs(pose.yaw) < 0.01


def test_wheel_speed_from_ticks_with_encoder_signs_first_tick_primes():
    cfg = HwConfig(base=BaseConfig(encoder_signs=(1, -1, 1, -1)))
    rig = make_base_rig(cfg, log=quiet_logger(), schedule=False)
    enc = rig.plant.encoders
    enc.ticks = [100, -100, 100, -100]
    rig.base.tick(0.0)
    np.testing.assert_array_equal(rig.base.wheel_speeds, 0.0)  # first tick: no velocity
    enc.ticks = [232, -232, 232, -232]  # +132 ticks = 0.1 rev in 0.1 s -> 2*pi*1 rad/s
    rig.base.tick(0.1)
    np.testing.assert_allclose(rig.base.wheel_speeds, 2 * math.pi)
    assert rig.base.odometry.pose.x == pytest.approx(2 * math.pi * 0.051 * 0.1)


def test_motor_signs_flip_duties():
    cfg = HwConfig(base=BaseConfig(motor_signs=(1, -1, -1, 1)))
    rig = make_base_rig(cfg, log=quiet_logger(), schedule=False)
    rig.mux.publish("auto", FWD, 0.0)
    duties = rig.base.tick(0.0)
    assert duties[0] > 0 and duties[1] < 0 and duties[2] < 0 and duties[3] > 0
    assert len(set(np.round(np.abs(duties), 12))) == 1


@pytest.mark.parametrize("name", ["pid_wheels_controller", "mirte_base_controller"])
@pytest.mark.parametrize("state", [ControllerState.MISSING, ControllerState.UNCONFIGURED, ControllerState.INACTIVE])
def test_zero_duties_unless_both_base_controllers_active(name, state):
    rig = make_base_rig(controllers={name: state}, log=quiet_logger())
    drive(rig, FWD, 1.0)
    assert rig.duty_log and all(np.all(d == 0) for _, d in rig.duty_log)
    assert rig.base.source == STOPPED_INACTIVE and rig.base.command == Twist()
    rig.controllers.heal(name)
    drive(rig, FWD, 0.3)
    assert np.all(rig.base.last_duties > 0)


def test_other_controllers_do_not_gate_the_base():
    rig = make_base_rig(controllers={"mirte_master_arm_controller": ControllerState.MISSING}, log=quiet_logger())
    drive(rig, FWD, 0.3)
    assert np.all(rig.base.last_duties > 0)


def test_estop_stops_same_tick_and_resets_pid():
    rig = make_base_rig(log=quiet_logger())
    drive(rig, FWD, 1.0)
    assert np.any(rig.base.pid.i_term != 0)
    rig.estop.set_soft(True)
    rig.base.tick(rig.clock.now() + 0.01)
    assert np.all(rig.base.last_duties == 0) and rig.base.source == STOPPED_ESTOP
    assert np.all(rig.base.pid.i_term == 0)


def test_silence_hands_bus_to_idle_and_base_stops():
    rig = make_base_rig(log=quiet_logger())
    drive(rig, FWD, 1.5)
    rig.scheduler.run_for(3.0)  # nobody publishes: auto times out after 0.5 s
    assert rig.base.source == "idle"
    assert np.all(np.abs(rig.base.wheel_speeds) < 0.1)
    assert np.all(np.abs(rig.base.last_duties) < 0.02)


def test_encoder_fault_stops_base_then_recovers():
    rig = make_base_rig(log=quiet_logger())
    drive(rig, FWD, 0.5)
    rig.plant.encoders.fail = True
    drive(rig, FWD, 0.3)
    assert rig.base.source == STOPPED_ENCODER_FAULT and np.all(rig.base.last_duties == 0)
    rig.plant.encoders.fail = False
    drive(rig, FWD, 0.3)
    assert rig.base.source == "auto" and np.all(rig.base.last_duties > 0)


def test_driver_write_failure_does_not_crash():
    rig = make_base_rig(log=quiet_logger())
    rig.plant.wheels.fail = True
    drive(rig, FWD, 0.3)
    assert rig.plant.wheels.log == []
    rig.plant.wheels.fail = False
    drive(rig, FWD, 0.2)
    assert rig.plant.wheels.log


def test_oversized_command_is_scaled_keeping_direction():
    rig = make_base_rig(log=quiet_logger(), schedule=False)
    big = Twist(2.0, 1.0, 0.0)  # needs 58.8 rad/s on two wheels: far above 6*pi
    rig.mux.publish("auto", big, 0.0)
    rig.base.tick(0.0)
    ref = rig.base.reference
    assert np.max(np.abs(ref)) == pytest.approx(6 * math.pi)
    direction = rig.base.mecanum.forward(ref)
    assert direction.vy / direction.vx == pytest.approx(0.5)
    assert np.all(np.abs(rig.base.last_duties) <= 1.0)
