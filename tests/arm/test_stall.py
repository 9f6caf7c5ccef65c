"""shoulder_lift's trips on the simulated servo: unload is recovered, a latch takes the arm out."""
import pytest

from arm.controller import ArmUnavailable
from arm.presets import preset

pytestmark = pytest.mark.slow

INSPECT = preset("inspect")


def test_unload_mid_move_is_reloaded_and_recommanded(rig):
    rig.run(0.3)
    rig.arm.preset("inspect")
    rig.run(0.6)  # about a third of the way
    rig.sim.faults.servo_stall("shoulder_lift")  # goes limp
    rig.run(1.0)
    assert not rig.sim.hal.servos.read_status(rig.ids["shoulder_lift"]).loaded
    rig.run(5.0)
    lift = rig.ids["shoulder_lift"]
    assert [(i, on) for _, i, on in rig.bus.loads] == [(lift, True)]  # one re-load
    assert rig.sim.hal.servos.read_status(lift).loaded
    assert rig.arm.available
    for j, q in INSPECT.items():
        assert rig.truth(j) == pytest.approx(q, abs=0.05), j


def test_unload_while_holding_sags_and_is_recovered(rig):
    rig.run(0.3)
    rig.arm.preset("inspect")
    rig.run(3.0)
    rig.sim.faults.servo_stall("shoulder_lift")
    rig.run(3.0)
    assert len(rig.bus.loads) == 1
    assert rig.truth("shoulder_lift") == pytest.approx(INSPECT["shoulder_lift"], abs=0.05)


def test_a_latch_is_reported_and_the_arm_taken_out_of_use(rig):
    told = []
    rig.arm.subscribe(told.append)
    rig.run(0.3)
    rig.sim.faults.servo_stall("shoulder_lift", mode="latch")
    rig.arm.preset("inspect")
    rig.run(4.0)
    assert not rig.arm.available
    assert len(told) == 1 and "shoulder_lift" in told[0] and "power cycle" in told[0]
    t = rig.sim.clock.now()
    with pytest.raises(ArmUnavailable, match="power cycle"):
        rig.arm.preset("home")
    with pytest.raises(ArmUnavailable):
        rig.arm.grip(-30)
    rig.run(2.0)
    assert rig.bus.writes(since=t) == 0  # out of use: nothing more on the bus
    assert len(told) == 1


def test_a_servo_that_stays_unloaded_counts_as_latched(rig):
    told = []
    rig.arm.subscribe(told.append)
    rig.run(0.3)
    rig.arm.preset("inspect")
    rig.run(3.0)
    rig.sim.faults.servo_stall("shoulder_lift")  # limp ...
    rig.sim.faults.servo_stall("shoulder_lift", mode="latch")  # ... and deaf to set_load
    rig.run(8.0)
    assert len(rig.bus.loads) == rig.robot.config.arm.stall.reload_attempts
    assert not rig.arm.available and "stays unloaded" in told[0]
