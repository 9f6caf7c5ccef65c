"""The arm's dead-band re-assert and stall handling again, on the Hiwonder driver over a real
pseudo-terminal against the bus emulator, on the wall clock (tests/arm runs them in the sim)."""
import time

import pytest

from arm.config import ArmConfig
from arm.controller import ArmController
from hw.config import ServoBusConfig
from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.hiwonder_protocol import Cmd
from hw.emulators.hiwonder_bus import EmuServo, HiwonderBusEmulator
from hw.wall_clock import WallClock
from mission.runtime.scheduler import Scheduler

SERVOS = ServoBusConfig()
IDS = {j: c.id for j, c in SERVOS.joints.items()}


class Rig:
    def __init__(self, emu: HiwonderBusEmulator):
        self.emu = emu
        self.bus = HiwonderBus.open(emu.path, timeout_s=0.1, retries=2)
        self.arm = ArmController(ArmConfig(), SERVOS, self.bus)
        self.reasons: list[str] = []
        self.arm.subscribe(self.reasons.append)
        self.scheduler = Scheduler(WallClock())
        self.scheduler.every("arm", self.arm.config.reassert.rate, self.arm.tick)

    def run(self, seconds: float) -> None:
        self.scheduler.run_for(seconds)

    def moves(self, joint: str, since: int = 0) -> list[int]:
        return [int.from_bytes(f.params[:2], "little") for f in self.emu.frames[since:]
                if f.cmd == Cmd.MOVE_TIME_WRITE and f.servo_id == IDS[joint]]

    def counts(self, joint: str, rad: float) -> int:
        return round(SERVOS.rad_to_counts(SERVOS.joints[joint], rad))


@pytest.fixture
def rig():
    with HiwonderBusEmulator({i: EmuServo() for i in IDS.values()}) as emu:
        r = Rig(emu)
        yield r
        r.bus.close()


def test_startup_pin_holds_the_live_pose_without_bus_writes(rig):
    rig.run(0.35)
    assert rig.arm.interface.pinned
    assert all(not rig.moves(j) for j in IDS)  # holding a pose costs no writes, nothing snaps to 0


def test_raw_write_is_overwritten_by_the_reassert(rig):
    rig.run(0.25)
    mark = len(rig.emu.frames)
    rig.bus.move(IDS["elbow"], 600, 0)  # a raw write past the controller (seed: gets overwritten)
    rig.run(1.0)  # drift trips the moved dead-band; the ramp back at 0.6 rad/s takes 0.7 s
    assert rig.moves("elbow", mark)[:2] == [600, 500]  # the raw write, then the re-assert
    assert rig.bus.read_position(IDS["elbow"]) == pytest.approx(500, abs=2)


def test_preset_goes_out_as_packets_towards_the_target(rig):
    rig.run(0.25)
    goal = dict(zip(("shoulder_pan", "shoulder_lift", "elbow", "wrist"), rig.arm.preset("inspect")))
    rig.run(0.6)
    assert not rig.moves("shoulder_pan")  # 500 counts is already its 0 rad: inside the dead-band
    for joint in ("shoulder_lift", "elbow", "wrist"):
        target, sent = rig.counts(joint, goal[joint]), rig.moves(joint)
        assert sent and abs(sent[-1] - target) < abs(500 - target) - 10, (joint, sent, target)  # on its way


def test_unloaded_shoulder_lift_is_reloaded_and_recommanded(rig):
    rig.run(0.25)
    rig.emu.servo(IDS["shoulder_lift"]).stall(sag_counts_per_s=60.0)
    end = time.monotonic() + 2.0
    while time.monotonic() < end and not rig.emu.servo(IDS["shoulder_lift"]).loaded:
        rig.run(0.1)
    lift = rig.emu.servo(IDS["shoulder_lift"])
    assert lift.loaded
    assert any(f.cmd == Cmd.LOAD_OR_UNLOAD_WRITE and f.params == b"\x01" for f in rig.emu.frames)
    rig.run(0.5)
    assert rig.bus.read_position(IDS["shoulder_lift"]) == pytest.approx(500, abs=3)  # back where it was held
    assert rig.arm.available


def test_latched_shoulder_lift_takes_the_arm_out_of_use(rig):
    rig.run(0.25)
    rig.emu.servo(IDS["shoulder_lift"]).latched = True
    goal = rig.arm.joint_vector()
    goal[1] -= 0.3  # shoulder_lift 0.3 rad down (0.5 s at 0.6 rad/s): far, and the servo ignores it
    rig.arm.move_to(goal)
    end = time.monotonic() + 6.0  # trajectory 0.5 s + the 1 s stuck delay, with room for a busy CI
    while time.monotonic() < end and rig.arm.available:
        rig.run(0.1)
    assert not rig.arm.available
    assert rig.reasons and "shoulder_lift" in rig.reasons[0] and "latched" in rig.reasons[0]
