"""The arm on the simulated robot: the real controller on the sim's Hiwonder servo model.

``CountingBus`` sits on the HAL boundary and records every bus write (move, load), so tests can
count what the dead-band loop sends.
"""
from __future__ import annotations

import pytest

from tests.fixtures import assemble, open_floor


class CountingBus:
    """A ServoBus that forwards to the sim's and logs every write with the sim time."""

    def __init__(self, bus, time_fn):
        self.bus = bus
        self.time = time_fn
        self.moves: list[tuple[float, int, int, int]] = []
        self.loads: list[tuple[float, int, bool]] = []

    def __getattr__(self, name):
        return getattr(self.bus, name)

    def move(self, servo_id, position, duration_ms):
        self.moves.append((self.time(), servo_id, position, duration_ms))
        self.bus.move(servo_id, position, duration_ms)

    def set_load(self, servo_id, loaded):
        self.loads.append((self.time(), servo_id, loaded))
        self.bus.set_load(servo_id, loaded)

    def writes(self, servo_id=None, since=0.0) -> int:
        return sum(1 for t, i, *_ in self.moves if t >= since and (servo_id is None or i == servo_id))


class ArmRig:
    def __init__(self, seed=0, **env):
        self.sim, self.robot = assemble(open_floor(), seed, **env)
        self.arm = self.robot.arm
        self.bus = CountingBus(self.sim.servos, self.sim.clock.now)
        self.arm.interface.bus = self.bus
        self.arm.stall.bus = self.bus
        self.ids = {j: c.id for j, c in self.robot.config.hw.servos.joints.items()}

    def run(self, seconds: float) -> None:
        self.robot.scheduler.run_for(seconds)

    def truth(self, joint: str) -> float:
        return self.sim.servos.joint_position(joint)

    def to_counts(self, joint: str, rad: float) -> int:
        cfg = self.robot.config.hw.servos
        return int(round(cfg.rad_to_counts(cfg.joints[joint], rad)))

    def close(self) -> None:
        self.sim.close()


@pytest.fixture
def rig():
    r = ArmRig()
    yield r
    r.close()
