"""Small simulated devices: IMU, power monitor (battery), e-stop button, LED strip.

The battery is a resistive 3S pack: open-circuit voltage falls linearly with charge used
(full 12.6 V to empty 11.1 V, the seed's power_watcher min_voltage) and the terminal voltage
sags by I*R under load, so driving visibly pulls the voltage down. A fault can force it, or add
a load (a stuck wheel, a short) that drains it faster than the robot's own work. While the robot
stands still on the dock the charger pushes current into the pack (CC-CV: constant, then
tapering), so the power monitor reads a negative current, as the INA226 does on the robot.
"""
from __future__ import annotations

from typing import Callable

import mujoco
import numpy as np

from hw.interfaces import ImuReading, PowerReading
from sim.config import BatteryConfig
from sim.engine import Engine


class SimImu:
    def __init__(self, engine: Engine, noise: tuple[float, float]):
        self.engine = engine
        m = engine.model
        self._acc = m.sensor_adr[engine.id(mujoco.mjtObj.mjOBJ_SENSOR, "imu_accel")]
        self._gyro = m.sensor_adr[engine.id(mujoco.mjtObj.mjOBJ_SENSOR, "imu_gyro")]
        self._noise = noise
        self._rng = np.random.default_rng([engine.config.seed, 3])

    def read(self) -> ImuReading:
        s = self.engine.data.sensordata
        acc = s[self._acc:self._acc + 3] + self._rng.normal(0, self._noise[0], 3)
        gyro = s[self._gyro:self._gyro + 3] + self._rng.normal(0, self._noise[1], 3)
        return ImuReading(self.engine.time, tuple(float(a) for a in acc), tuple(float(g) for g in gyro))


DOCKED_LOAD = 0.05
"""The dock's contacts carry current only to a robot at rest on them: wheel duties summed below
this (a robot turning or driving over the dock is not charging)."""


class SimBattery:
    """Implements the HAL's PowerMonitor. ``load()`` returns the drivetrain's duty load (0..4)."""

    def __init__(self, engine: Engine, config: BatteryConfig, load: Callable[[], float],
                 on_dock: Callable[[], bool] = lambda: False):
        self.engine = engine
        self.config = config
        self._load = load
        self._on_dock = on_dock
        self._used_ah = 0.0
        self._t = engine.time
        self.forced_voltage: float | None = None
        self.extra_load: tuple[float, float] = (0.0, 0.0)
        """A fault's extra draw: (amps, until sim time)."""

    @property
    def charge(self) -> float:
        """The pack's true charge, 0..1 (for judging only)."""
        return max(0.0, 1.0 - self._used_ah / self.config.capacity_ah)

    def _current(self) -> float:
        c = self.config
        load = self._load()
        if load < DOCKED_LOAD and self._on_dock():  # the charger carries the robot's load and charges the pack
            missing = (1.0 - self.charge) / max(1e-9, 1.0 - c.charge_taper_from)
            return -c.charge_current * min(1.0, missing)
        amps, until = self.extra_load
        return c.idle_current + c.stall_current * load + (amps if self.engine.time < until else 0.0)

    def _integrate(self) -> float:
        now = self.engine.time
        current = self._current()
        self._used_ah = max(0.0, self._used_ah + current * max(0.0, now - self._t) / 3600.0)
        self._t = now
        return current

    def read(self) -> PowerReading:
        current = self._integrate()
        if self.forced_voltage is not None:
            return PowerReading(self.engine.time, self.forced_voltage, current)
        c = self.config
        v = c.empty_voltage + (c.full_voltage - c.empty_voltage) * self.charge - c.internal_resistance * current
        return PowerReading(self.engine.time, v, current)

    def voltage_mv(self) -> int:
        return int(round(self.read().voltage * 1000))


class SimEStopButton:
    """The physical mushroom button. ``pressed_level`` is how the sim robot is wired."""

    def __init__(self, pressed_level: int):
        self.pressed_level = pressed_level
        self.pressed = False

    def read_level(self) -> int:
        return self.pressed_level if self.pressed else 1 - self.pressed_level


class SimLedStrip:
    """Decodes wire bytes with the strip's *physical* colour order and shows pixel 0 on the
    chassis' ``led_strip`` geom, so a wrong colour-order config shows the wrong colour."""

    def __init__(self, engine: Engine, num_leds: int, physical_order: str):
        self.engine = engine
        self.num_leds = num_leds
        self.order = physical_order
        self.wire = b""
        self._geom = engine.id(mujoco.mjtObj.mjOBJ_GEOM, "led_strip")

    def write(self, wire: bytes) -> None:
        self.wire = bytes(wire)
        if len(wire) >= 3:
            rgb = self.pixel(0)
            self.engine.model.geom_rgba[self._geom, :3] = np.array(rgb) / 255.0

    def pixel(self, i: int) -> tuple[int, int, int]:
        chunk = dict(zip(self.order, self.wire[3 * i:3 * i + 3]))
        return chunk["R"], chunk["G"], chunk["B"]
