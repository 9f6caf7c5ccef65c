"""Zero-offset calibration on the byte-level Hiwonder bus emulator (the real driver over a pty)."""
import numpy as np
import pytest

from arm.calibration import Calibration, CalibrationError, Phase
from arm.config import CalibrationConfig
from hw.config import ServoBusConfig
from hw.drivers.hiwonder import HiwonderBus
from hw.emulators.hiwonder_bus import HiwonderBusEmulator
from tests.fixtures import assemble, open_floor

SERVOS = ServoBusConfig()


def zero(joint: str) -> float:
    return SERVOS.joints[joint].home / SERVOS.centideg_per_count


@pytest.fixture
def bus():
    with HiwonderBusEmulator() as emu:
        drv = HiwonderBus.open(emu.path, 115200, timeout_s=0.05, retries=2)
        try:
            yield emu, drv
        finally:
            drv.close()


def ids(*joints):
    return [SERVOS.joints[j].id for j in joints]


def sample(cal, emu, t0=0.0, jitter=None):
    """Tick through the ~2 s of sampling at 10 Hz; ``jitter(k)`` moves servos between reads."""
    cal.commit(t0)
    t = t0
    k = 0
    while cal.phase is Phase.SAMPLING:
        if jitter:
            jitter(k)
        t += 0.1
        k += 1
        cal.tick(t)
    return t


def test_start_unloads_commit_writes_offsets_and_pan_is_skipped(bus):
    emu, drv = bus
    posed = {"shoulder_pan": 9, "shoulder_lift": 7, "elbow": -5, "wrist": 12, "gripper": -3}  # counts off zero
    for j, d in posed.items():
        emu.servo(SERVOS.joints[j].id).place(zero(j) + d)
    cal = Calibration(drv, SERVOS, CalibrationConfig())
    cal.start()
    drv.ping(2)  # writes have no reply: a read after them means the emulator handled them
    assert cal.phase is Phase.POSING
    assert [emu.servo(i).loaded for i in ids("shoulder_lift", "elbow", "wrist", "gripper")] == [False] * 4
    assert emu.servo(SERVOS.joints["shoulder_pan"].id).loaded
    end = sample(cal, emu)
    drv.ping(2)
    assert end == pytest.approx(2.0)
    got = {o.joint: (o.status, o.offset) for o in cal.status().outcomes}
    assert set(got) == {"shoulder_lift", "elbow", "wrist", "gripper"}
    for j in got:
        s = emu.servo(SERVOS.joints[j].id)
        assert got[j][0] == "written"
        assert abs(got[j][1] - posed[j]) <= 1
        assert s.saved_offset == got[j][1] == s.offset  # adjusted, then persisted
        assert abs(drv.read_position(SERVOS.joints[j].id) - zero(j)) <= 1  # now reads zero here
        assert s.loaded  # re-loaded at the end
    pan = emu.servo(SERVOS.joints["shoulder_pan"].id)
    assert pan.offset == 0 and pan.saved_offset == 0
    assert cal.phase is Phase.IDLE and "4 of 4" in cal.status().note


def test_noisy_and_misassembled_joints_are_rejected(bus):
    emu, drv = bus
    for j in ("shoulder_lift", "elbow", "wrist", "gripper"):
        emu.servo(SERVOS.joints[j].id).place(zero(j))
    emu.servo(SERVOS.joints["elbow"].id).place(zero("elbow") + 60)  # 14 deg off: horn on the wrong spline
    rng = np.random.default_rng(1)
    wrist = emu.servo(SERVOS.joints["wrist"].id)
    cal = Calibration(drv, SERVOS, CalibrationConfig())
    cal.start()
    sample(cal, emu, jitter=lambda k: wrist.place(zero("wrist") + rng.integers(-12, 13)))  # hand still moving
    drv.ping(2)
    got = {o.joint: o for o in cal.status().outcomes}
    assert got["wrist"].status == "noisy"
    assert got["elbow"].status == "misassembled" and got["elbow"].offset == 60
    assert got["shoulder_lift"].status == "written" and got["gripper"].status == "written"
    assert emu.servo(SERVOS.joints["elbow"].id).saved_offset == 0
    assert wrist.saved_offset == 0


def test_cancel_reloads_and_writes_nothing(bus):
    emu, drv = bus
    cal = Calibration(drv, SERVOS, CalibrationConfig())
    with pytest.raises(CalibrationError, match="start it first"):
        cal.commit(0.0)
    cal.start()
    with pytest.raises(CalibrationError, match="already posing"):
        cal.start()
    cal.commit(0.0)
    cal.tick(0.1)
    cal.cancel()
    drv.ping(2)
    assert cal.phase is Phase.IDLE and "cancelled" in cal.status().note
    assert all(emu.servo(i).loaded and emu.servo(i).saved_offset == 0 for i in range(2, 7))


def test_calibration_suspends_the_arm_and_resumes_it():
    class Arm:
        def __init__(self):
            self.calls = []

        def suspend(self):
            self.calls.append("suspend")

        def resume(self):
            self.calls.append("resume")

    with HiwonderBusEmulator() as emu:
        drv = HiwonderBus.open(emu.path, 115200, timeout_s=0.05, retries=2)
        try:
            arm = Arm()
            cal = Calibration(drv, SERVOS, CalibrationConfig(), arm=arm)
            cal.start()
            cal.cancel()
            assert arm.calls == ["suspend", "resume"]
        finally:
            drv.close()


@pytest.mark.slow
def test_the_sim_backend_is_a_clear_error():
    sim, robot = assemble(open_floor())
    try:
        with pytest.raises(CalibrationError, match="hardware only"):
            Calibration(sim.hal.servos, robot.config.hw.servos, robot.config.arm.calibration)
    finally:
        sim.close()
