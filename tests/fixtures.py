"""Shared test builders: fake HAL devices and a small base-control rig.

The fakes sit exactly at the HAL's device level (``hw.interfaces``): the wheel driver receives
duty vectors and the encoders hand back integer ticks, so everything above them (PID, mecanum,
mux, e-stop, odometry) runs the real code. ``WheelPlant`` joins the two with a first-order wheel
model (tau 0.15 s, 100 % duty = 6*pi rad/s, the hardware reference's drive scale) and is driven
by ``SimClock``'s advance callback, so time in a test moves only through the scheduler.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from hw.base_controller import BaseController
from hw.config import HwConfig
from hw.controller_manager import ControllerManager, ControllerState
from hw.estop import EStopBridge
from hw.interfaces import DeviceError
from hw.twist_mux import TwistMux
from sim.clock import SimClock
from mission.runtime.scheduler import Scheduler


class FakeWheels:
    """A wheel driver that records every duty vector it receives, with the time it arrived."""

    def __init__(self, time_fn=lambda: 0.0):
        self._time_fn = time_fn
        self.duties = np.zeros(4)
        self.log: list[tuple[float, np.ndarray]] = []
        self.fail = False

    def set_duties(self, duties: Sequence[float]) -> None:
        if self.fail:
            raise DeviceError("PCA9685 did not acknowledge")
        d = np.array(duties, dtype=float)
        assert d.shape == (4,), d.shape
        assert np.all(np.abs(d) <= 1.0), d
        self.duties = d
        self.log.append((self._time_fn(), d))


class FakeEncoders:
    """Accumulated quadrature ticks, set directly or by a ``WheelPlant``."""

    def __init__(self, ticks: Sequence[int] = (0, 0, 0, 0)):
        self.ticks = list(ticks)
        self.fail = False
        self.reads = 0

    def read_ticks(self) -> tuple[int, ...]:
        if self.fail:
            raise DeviceError("encoder GPIO lines unavailable")
        self.reads += 1
        return tuple(int(t) for t in self.ticks)


class FakeButton:
    """The e-stop pin: a raw level, or an exception to raise on read."""

    def __init__(self, level: int = 0):
        self.level = level
        self.error: Exception | None = None

    def read_level(self) -> int:
        if self.error is not None:
            raise self.error
        return self.level


class FakeStrip:
    def __init__(self, num_leds: int = 8):
        self.num_leds = num_leds
        self.writes: list[bytes] = []

    def write(self, wire: bytes) -> None:
        assert len(wire) == 3 * self.num_leds
        self.writes.append(bytes(wire))


class WheelPlant:
    """Four first-order wheels behind a FakeWheels driver and FakeEncoders.

    ``advance_to(t)`` integrates exactly (zero-order-hold duty, exponential response) and adds
    the travelled angle to the encoders; ``stalled`` wheels are held at zero speed. Duties
    inside the 10 % dead-zone (hardware reference) do not turn the wheel, as in the sim motor.
    """

    def __init__(self, ticks_per_rev: int = 1320, max_speed: float = 6 * math.pi, tau: float = 0.15,
                 dead_zone: float = 0.10):
        self.ticks_per_rev = ticks_per_rev
        self.max_speed = max_speed
        self.tau = tau
        self.dead_zone = dead_zone
        self.t = 0.0
        self.speeds = np.zeros(4)
        self.stalled = np.zeros(4, dtype=bool)
        self._angle_ticks = np.zeros(4)
        self.wheels = FakeWheels(lambda: self.t)
        self.encoders = FakeEncoders()

    def advance_to(self, t: float) -> None:
        dt = t - self.t
        if dt <= 0:
            return
        d, dz = self.wheels.duties, self.dead_zone
        target = np.where(np.abs(d) < dz, 0.0, np.sign(d) * (np.abs(d) - dz) / (1.0 - dz)) * self.max_speed
        a = math.exp(-dt / self.tau)
        w0 = np.where(self.stalled, 0.0, self.speeds)
        travelled = target * dt + (w0 - target) * self.tau * (1.0 - a)  # integral of w over dt
        w1 = target + (w0 - target) * a
        travelled = np.where(self.stalled, 0.0, travelled)
        self.speeds = np.where(self.stalled, 0.0, w1)
        self._angle_ticks += travelled * self.ticks_per_rev / (2 * math.pi)
        self.encoders.ticks = [int(math.floor(x)) for x in self._angle_ticks]
        self.t = t


def quiet_logger(name: str = "lupin.test") -> logging.Logger:
    """A logger that swallows the e-stop banner in bulk tests (caplog still works elsewhere)."""
    log = logging.getLogger(name)
    log.propagate = False
    if not log.handlers:
        log.addHandler(logging.NullHandler())
    return log


@dataclass
class BaseRig:
    config: HwConfig
    clock: SimClock
    scheduler: Scheduler
    plant: WheelPlant
    button: FakeButton
    mux: TwistMux
    estop: EStopBridge
    controllers: ControllerManager
    base: BaseController
    log: logging.Logger = field(repr=False, default=None)

    @property
    def duty_log(self) -> list[tuple[float, np.ndarray]]:
        return self.plant.wheels.log


def make_base_rig(
    config: HwConfig | None = None,
    controllers: dict[str, ControllerState] | None = None,
    log: logging.Logger | None = None,
    schedule: bool = True,
) -> BaseRig:
    """The base chain on fake devices: plant + mux + e-stop + controller manager + BaseController,
    with the 10 Hz control tick and the 5 Hz e-stop publish registered on a sim-clock scheduler."""
    config = config or HwConfig()
    plant = WheelPlant(config.base.ticks_per_rev, config.base.max_wheel_speed)
    clock = SimClock(advance=plant.advance_to)
    scheduler = Scheduler(clock)
    released = 1 - config.estop.engaged_level
    button = FakeButton(level=released)
    mux = TwistMux(config.mux)
    estop = EStopBridge(config.estop, button, log)
    manager = ControllerManager(config.controllers, controllers or {})
    base = BaseController(config.base, plant.wheels, plant.encoders, mux, estop, manager, log)
    if schedule:
        scheduler.every("base", config.base.control_rate, base.tick)
        scheduler.every("estop", config.estop.publish_rate, estop.publish)
    return BaseRig(config, clock, scheduler, plant, button, mux, estop, manager, base, log)


# --- the simulated robot -----------------------------------------------------------------------

def open_floor(spawn=(3.0, 3.0, 0.0), size=(8.0, 6.0)):
    """An empty greenhouse: nothing to bump into, so truth is what the wheels achieved."""
    from sim.world import Floor, Pose2, World

    return World(name="open", floor=Floor(x=size[0], y=size[1]),
                 spawn=Pose2(x=spawn[0], y=spawn[1], yaw=spawn[2]), pots=[])


def assemble(world, seed: int = 0, **env):
    """A sim runtime (MuJoCo robot + hardware services, scheduled) -> (SimRobot, Robot)."""
    from mission.runtime.config import load_config
    from mission.runtime.sim_runtime import start_sim_runtime

    rt = start_sim_runtime(world, load_config(env={"LUPIN_SIM__SEED": str(seed), **env}))
    return rt.sim, rt.robot
