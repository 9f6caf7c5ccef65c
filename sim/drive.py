"""The simulated mecanum drivetrain: four DC motors, their encoders, and traction.

Each wheel is a MuJoCo hinge driven by a velocity servo whose target is the PWM duty times the
top speed (100 % = 6*pi rad/s, hardware reference) past a 10 % dead-zone; the wheel's armature
over the servo gain makes its speed follow that target with a first-order lag (``motor_tau``).
Encoders count the wheel hinge angle at 1320 ticks/rev.

Mecanum rollers are not simulated. Instead, every ``drive_update`` the wheels' *measured*
speeds go through the mecanum forward kinematics (less a little roller slip) and become the
targets of three body-frame traction servos on the chassis, whose force is capped at what the
tyres can push. Against a pot or a wall the chassis stops while the wheels keep turning, so
wheel odometry diverges from ground truth exactly as it does on the robot.
"""
from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from hw.config import BaseConfig
from hw.interfaces import WHEELS
from hw.mecanum import Mecanum
from sim.config import DriveConfig
from sim.engine import Engine

WHEEL_JOINTS = tuple(f"wheel_{w}" for w in WHEELS)
TRACTION = ("drive_vx", "drive_vy", "drive_wz")


class SimDrive:
    """Implements the HAL's WheelDriver and WheelEncoders on the MuJoCo model."""

    def __init__(self, engine: Engine, drive: DriveConfig, base: BaseConfig):
        self.engine = engine
        self.drive = drive
        self.base = base
        self.mecanum = Mecanum(base.wheel_radius, base.lx_plus_ly)
        m = engine.model
        self._wheel_act = np.array([engine.actuator(j) for j in WHEEL_JOINTS])
        self._wheel_qpos = np.array([engine.joint_qpos(j) for j in WHEEL_JOINTS])
        self._wheel_dof = np.array([engine.joint_dof(j) for j in WHEEL_JOINTS])
        self._traction = np.array([engine.actuator(a) for a in TRACTION])
        # first-order lag: tau = armature / kv
        kv = m.actuator_gainprm[self._wheel_act, 0]
        m.dof_armature[self._wheel_dof] = drive.motor_tau * kv
        limits = (drive.traction_force, drive.traction_force, drive.traction_torque)
        for act, limit in zip(self._traction, limits):
            m.actuator_forcelimited[act] = 1
            m.actuator_forcerange[act] = (-limit, limit)
        self._slip = np.asarray(drive.slip)
        self._rng = np.random.default_rng([engine.config.seed, 4])
        self._duties = np.zeros(4)
        self.powered = True
        self.listeners: list[Callable[[float, np.ndarray], None]] = []
        """Called with (sim time, duties) on every write: how a judge sees what reached the motors."""
        engine.attach(self)

    # --- HAL: WheelDriver --------------------------------------------------------------
    def set_duties(self, duties: Sequence[float]) -> None:
        d = np.clip(np.asarray(duties, dtype=float), -1.0, 1.0)
        if d.shape != (4,) or not np.all(np.isfinite(d)):
            raise ValueError(f"expected 4 finite duties, got {duties!r}")
        self._duties = d
        for listener in self.listeners:
            listener(self.engine.time, d.copy())
        mag = np.abs(d)
        effective = np.where(mag < self.drive.dead_zone, 0.0, np.sign(d) * (mag - self.drive.dead_zone) / (1.0 - self.drive.dead_zone))
        if not self.powered:
            effective[:] = 0.0
        self.engine.data.ctrl[self._wheel_act] = effective * self.base.max_wheel_speed

    @property
    def duties(self) -> np.ndarray:
        return self._duties.copy()

    # --- HAL: WheelEncoders ------------------------------------------------------------
    def read_ticks(self) -> tuple[int, ...]:
        angle = self.engine.data.qpos[self._wheel_qpos]
        ticks = np.floor(angle * self.base.ticks_per_rev / (2 * math.pi))
        return tuple(int(t) for t in ticks)

    # --- traction ----------------------------------------------------------------------
    def pre_chunk(self, t: float) -> None:
        tw = self.mecanum.forward(self.engine.data.qvel[self._wheel_dof])
        self.engine.data.ctrl[self._traction] = np.array((tw.vx, tw.vy, tw.wz)) * (1.0 - np.minimum(self._draw_slip(), 1.0))

    def _draw_slip(self) -> np.ndarray:
        """This update's slip per axis: gamma-distributed with the configured mean and jitter."""
        jitter = self.drive.slip_jitter
        if jitter == 0.0:
            return self._slip
        mean = np.maximum(self._slip, 1e-9)
        return self._rng.gamma(mean * mean / (jitter * jitter), jitter * jitter / mean)

    def load(self) -> float:
        """Sum of |effective duty| over the wheels (0..4), for the battery's current draw."""
        ctrl = self.engine.data.ctrl[self._wheel_act]
        return float(np.sum(np.abs(ctrl))) / self.base.max_wheel_speed

