"""The gripper path on the simulated jaw: operator degrees -> the gripper controller -> result."""
import pytest

from arm.gripper import GripperResult

pytestmark = pytest.mark.slow


def test_close_and_open_reach_the_urdf_ends(rig):
    rig.run(0.3)
    goal = rig.arm.grip(30)  # +30 = CLOSED on Mirte-247264
    assert goal == pytest.approx(0.25)
    assert rig.arm.gripper.result is GripperResult.MOVING
    rig.run(2.0)
    assert rig.arm.gripper.result is GripperResult.REACHED
    assert rig.truth("gripper") == pytest.approx(0.25, abs=0.03)
    assert rig.arm.gripper.open() == pytest.approx(-0.20)
    rig.run(2.0)
    assert rig.arm.gripper.result is GripperResult.REACHED
    assert rig.truth("gripper") == pytest.approx(-0.20, abs=0.03)


def test_goals_go_through_the_controller_and_are_clamped(rig):
    rig.run(0.3)
    jaw = rig.ids["gripper"]
    rig.arm.grip(75)  # beyond the operator window: clamped to +30 -> 0.25 rad
    rig.run(1.5)
    sent = [p for _, i, p, _ in rig.bus.moves if i == jaw]
    assert sent and sent[-1] == rig.to_counts("gripper", 0.25)
    assert rig.arm.interface.command("gripper") == pytest.approx(0.25)


def test_a_jaw_that_does_not_move_is_stalled(rig):
    rig.run(0.3)
    rig.sim.faults.servo_stall("gripper", mode="latch")
    rig.arm.grip(-30)
    rig.run(0.5)
    assert rig.arm.gripper.result is GripperResult.MOVING
    rig.run(1.5)
    assert rig.arm.gripper.result is GripperResult.STALLED
