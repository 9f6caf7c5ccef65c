"""The trajectory controller and its dead-band write loop on the simulated Hiwonder servos."""
import numpy as np
import pytest

from arm.controller import ArmUnavailable
from arm.presets import ARM_JOINTS, UnknownPreset, preset
from tests.arm.conftest import ArmRig

pytestmark = pytest.mark.slow

INSPECT = preset("inspect")


def at_inspect(rig):
    rig.run(0.3)
    rig.arm.preset("inspect")
    rig.run(3.0)
    assert rig.arm.at(INSPECT)
    return rig


def test_preset_is_one_trajectory_of_all_four_joints(rig):
    rig.run(0.3)
    goal = rig.arm.preset("inspect")
    assert np.allclose(goal, [INSPECT[j] for j in ARM_JOINTS])
    rig.run(0.1)
    traj = rig.arm.trajectory
    assert traj.label == "inspect" and traj.duration == pytest.approx(0.9 / 0.6, abs=0.02)  # elbow 0 -> 0.9
    rig.run(traj.duration / 2)
    moved = [abs(rig.truth(j)) for j in ("shoulder_lift", "elbow", "wrist")]
    assert all(0.1 < m < 0.7 for m in moved), moved  # all three under way together
    rig.run(2.0)
    for j in ARM_JOINTS:
        assert rig.truth(j) == pytest.approx(INSPECT[j], abs=0.05)
    with pytest.raises(UnknownPreset):
        rig.arm.preset("wave")


def test_goals_outside_the_windows_are_clamped(rig):
    rig.run(0.3)
    goal = rig.arm.move_to([0.0, -3.0, 0.5, 3.0])
    assert goal[1] == pytest.approx(np.radians(-86)) and goal[3] == pytest.approx(np.radians(88))


def test_holding_a_pose_sends_nothing(rig):
    at_inspect(rig)
    t = rig.sim.clock.now()
    rig.run(5.0)
    assert rig.bus.writes(since=t) == 0


def test_no_resend_below_the_deadbands(rig):
    at_inspect(rig)
    t = rig.sim.clock.now()
    elbow = rig.ids["elbow"]
    rig.arm.move_to({**INSPECT, "elbow": INSPECT["elbow"] + 0.04})  # command change 0.04 < 0.05
    rig.run(1.0)
    rig.bus.bus.move(elbow, rig.to_counts("elbow", INSPECT["elbow"] + 0.03), 100)  # a raw nudge < 0.05 rad
    rig.run(2.0)
    assert rig.bus.writes(since=t) == 0
    assert rig.truth("elbow") - INSPECT["elbow"] > 0.04  # left alone (0.03 plus its gravity sag)


def test_a_raw_write_is_overwritten(rig):
    at_inspect(rig)
    t = rig.sim.clock.now()
    elbow = rig.ids["elbow"]
    rig.bus.bus.move(elbow, rig.to_counts("elbow", 0.3), 200)  # bypasses the controller
    lowest = INSPECT["elbow"]
    for _ in range(10):
        rig.run(0.05)
        lowest = min(lowest, rig.truth("elbow"))
    assert lowest < INSPECT["elbow"] - 0.1  # the raw write did move it ...
    rig.run(2.0)
    assert rig.truth("elbow") == pytest.approx(INSPECT["elbow"], abs=0.04)  # ... and it was snapped back
    assert 1 <= rig.bus.writes(elbow, since=t) <= 3
    assert rig.bus.writes(since=t) == rig.bus.writes(elbow, since=t)  # nobody else was touched


def test_gravity_sag_past_the_deadband_self_corrects(rig):
    """The lift drops while nothing is looking (a brown-out: torque off, then back on where it
    sagged to); the moved dead-band trips and re-commands it to its setpoint."""
    at_inspect(rig)
    lift = rig.ids["shoulder_lift"]
    rig.sim.servos.unload("shoulder_lift")
    rig.sim.clock.wait_until(rig.sim.clock.now() + 0.15)  # physics only: no controller tick
    rig.sim.servos.set_load(lift, True)  # holds where it sagged to
    sagged = rig.truth("shoulder_lift")
    assert sagged < INSPECT["shoulder_lift"] - 0.08
    t = rig.sim.clock.now()
    rig.run(2.0)
    assert rig.truth("shoulder_lift") == pytest.approx(INSPECT["shoulder_lift"], abs=0.05)
    assert rig.bus.writes(lift, since=t) >= 1
    assert not rig.bus.loads  # it was loaded: a plain dead-band re-assert, no re-load


def test_startup_pin_a_jaw_resting_away_from_zero_does_not_move(rig):
    rig.sim.servos.place({"gripper": 0.2, "wrist": -0.5})  # where the jaw and wrist rest at power-up
    with pytest.raises(ArmUnavailable, match="no complete joint state"):
        rig.arm.preset("home")
    rig.run(3.0)
    assert rig.arm.interface.pinned
    assert rig.truth("gripper") == pytest.approx(0.2, abs=0.01)
    assert rig.truth("wrist") == pytest.approx(-0.5, abs=0.02)
    assert rig.bus.writes() == 0
    assert rig.arm.interface.command("gripper") == pytest.approx(0.2, abs=0.01)


def test_first_state_waits_for_every_joint(rig):
    real = rig.bus.bus.read_position
    wrist = rig.ids["wrist"]

    def flaky(i):
        if i == wrist:
            raise __import__("hw.interfaces", fromlist=["DeviceError"]).DeviceError("no reply")
        return real(i)

    rig.bus.read_position = flaky
    rig.run(1.0)
    assert not rig.arm.interface.pinned and rig.bus.writes() == 0
    del rig.bus.read_position
    rig.run(0.2)
    assert rig.arm.interface.pinned


def test_stuck_guard_commands_a_stuck_joint_to_where_it_is_once(rig):
    rig.run(0.3)
    rig.sim.faults.servo_stall("elbow", mode="latch")  # ignores commands
    rig.arm.preset("inspect")
    rig.run(2.0)  # the trajectory (1.5 s) and its final point are sent; the elbow never moved
    elbow = rig.ids["elbow"]
    t = rig.sim.clock.now()
    rig.run(1.5)
    assert rig.arm.interface.command("elbow") == pytest.approx(rig.truth("elbow"), abs=0.02)
    assert rig.bus.writes(elbow, since=t) == 1
    t = rig.sim.clock.now()
    rig.run(3.0)
    assert rig.bus.writes(elbow, since=t) == 0
    assert rig.arm.available  # the elbow is not a stall-watched joint


def test_commands_need_the_arm_controller_active(rig):
    rig.run(0.3)
    rig.robot.controllers.deactivate("mirte_master_arm_controller")
    with pytest.raises(ArmUnavailable, match="mirte_master_arm_controller is inactive"):
        rig.arm.preset("home")
    rig.arm.grip(0)  # the gripper controller is separate and still active


def test_idle_timeout_parks_at_home():
    rig = ArmRig(LUPIN_ARM__MOTION__IDLE_TIMEOUT="5")
    try:
        at_inspect(rig)  # the move ends at ~1.8 s, the check at 3.3 s
        rig.run(3.0)
        assert rig.arm.at(INSPECT)  # idle 4.5 s: not yet
        rig.run(4.0)
        assert rig.arm.at(preset("home"))
        t = rig.sim.clock.now()
        rig.run(8.0)
        assert rig.bus.writes(since=t) == 0  # parked and left alone
    finally:
        rig.close()


def test_garbage_reads_never_crash_the_loop_or_move_the_arm(rig):
    at_inspect(rig)
    real = rig.bus.bus.read_position
    garbage = iter([65535, -30000, None, "x"] * 10)

    def noisy(i):
        if i == rig.ids["elbow"]:
            return next(garbage)
        return real(i)

    rig.bus.read_position = noisy
    t = rig.sim.clock.now()
    rig.run(2.0)
    assert rig.bus.writes(since=t) == 0
    assert rig.arm.available and rig.arm.interface.read_errors >= 20
    del rig.bus.read_position
    rig.run(0.5)
    assert rig.arm.interface.position("elbow") == pytest.approx(rig.truth("elbow"), abs=0.01)


def test_suspend_stops_driving_and_resume_repins_the_live_pose(rig):
    at_inspect(rig)
    rig.arm.suspend()
    with pytest.raises(ArmUnavailable, match="calibrated"):
        rig.arm.preset("home")
    t = rig.sim.clock.now()
    rig.bus.bus.move(rig.ids["wrist"], rig.to_counts("wrist", -0.3), 200)  # the operator poses it
    rig.run(1.0)
    assert rig.bus.writes(since=t) == 0  # nothing fought the operator
    rig.arm.resume()
    rig.run(1.0)
    assert rig.bus.writes(since=t) == 0  # re-pinned where it was left, no snap back
    assert rig.arm.interface.command("wrist") == pytest.approx(rig.truth("wrist"), abs=0.02)
    assert rig.truth("wrist") == pytest.approx(-0.3, abs=0.05)
