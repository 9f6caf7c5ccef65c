"""The same trajectory controller on the byte-level Hiwonder bus emulator, through the real
driver over a pseudo-terminal: the startup pin, counts on the wire, the dead-band re-assert.

Runtime time here is a counter the test advances (the controller never reads a clock); the
emulated servos ramp on their own time, so assertions are about what crosses the wire."""
import pytest

from arm.config import ArmConfig
from arm.controller import ArmController
from arm.presets import ARM_JOINTS
from hw.config import ServoBusConfig
from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.hiwonder_protocol import Cmd
from hw.emulators.hiwonder_bus import HiwonderBusEmulator

SERVOS = ServoBusConfig()
REST = {"shoulder_pan": 0.0, "shoulder_lift": -0.2, "elbow": 0.5, "wrist": -1.0, "gripper": 0.18}


def counts(joint, rad):
    return int(round(SERVOS.rad_to_counts(SERVOS.joints[joint], rad)))


def moves(emu, since=0):
    return [(f.servo_id, int.from_bytes(f.params[:2], "little")) for f in emu.frames[since:]
            if f.cmd == Cmd.MOVE_TIME_WRITE]


@pytest.fixture
def rig():
    with HiwonderBusEmulator() as emu:
        for j, q in REST.items():
            emu.servo(SERVOS.joints[j].id).place(SERVOS.rad_to_counts(SERVOS.joints[j], q))
        drv = HiwonderBus.open(emu.path, 115200, timeout_s=0.05, retries=2)
        arm = ArmController(ArmConfig(), SERVOS, drv)
        clock = {"t": 0.0}

        def run(seconds):
            for _ in range(round(seconds * 10)):
                clock["t"] += 0.1
                arm.tick(clock["t"])
        try:
            yield emu, drv, arm, run
        finally:
            drv.close()


def test_startup_pin_holds_the_resting_pose_with_nothing_on_the_wire(rig):
    emu, drv, arm, run = rig
    run(1.0)
    assert arm.interface.pinned
    assert moves(emu) == []
    for j, q in REST.items():
        assert arm.interface.command(j) == pytest.approx(q, abs=0.005)


def test_a_move_goes_out_in_counts_and_ends_on_the_goal(rig):
    emu, drv, arm, run = rig
    run(0.3)
    goal = {**{j: REST[j] for j in ARM_JOINTS}, "elbow": 0.9}
    arm.move_to(goal)
    run(2.0)
    sent = [p for i, p in moves(emu) if i == SERVOS.joints["elbow"].id]
    assert len(sent) >= 3 and sent == sorted(sent)  # a ramp, one way
    assert sent[-1] == counts("elbow", 0.9)
    assert {i for i, _ in moves(emu)} == {SERVOS.joints["elbow"].id}  # nobody else moved


def test_a_raw_move_on_the_bus_is_reasserted_and_holding_is_silent(rig):
    emu, drv, arm, run = rig
    run(0.5)
    n = len(emu.frames)
    run(2.0)
    assert moves(emu, n) == []  # holding: no writes
    wrist = SERVOS.joints["wrist"].id
    emu.servo(wrist).place(counts("wrist", -0.6))  # someone moved it behind our back
    n = len(emu.frames)
    run(0.3)
    assert moves(emu, n) == [(wrist, counts("wrist", REST["wrist"]))]
