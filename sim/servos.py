"""The simulated Hiwonder servo bus (ids 2-6: shoulder_pan ... gripper).

Semantics follow the LX-series protocol, not an idealised joint: ``move(position, time)`` ramps
the servo's setpoint linearly from where the joint *is* to the target over ``time``; positions
are 0..1000 counts over 240 deg, clamped to the servo's software angle limits; the angle
offset (1 unit = 0.24 deg) shifts both commands and reads; reads carry +-1 count of noise.
Each joint is a MuJoCo position servo with finite stiffness and a stall-torque cap, so gravity
really sags shoulder_lift (which is what the seed's dead-band re-assert corrects).

Faults (seed, "shoulder_lift will trip if held against gravity"):
- unload: torque drops, the joint goes back-drivable and sags; ``set_load(True)`` re-loads it.
- latch: commands are ignored while the encoder still reports position (needs a power cycle).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from hw.config import ServoBusConfig, ServoCalib
from hw.interfaces import DeviceError, ServoStatus
from sim.engine import Engine

OFFSET_LIMIT = 125  # ANGLE_OFFSET_ADJUST range, +-125 units = +-30 deg


@dataclass
class _Servo:
    joint: str
    calib: ServoCalib
    act: int
    qpos: int
    kp: float
    setpoint: float = 0.0
    start: float = 0.0
    target: float = 0.0
    t0: float = 0.0
    duration: float = 0.0
    offset: int = 0
    loaded: bool = True
    latched: bool = False


class SimServoBus:
    """Implements the HAL's ServoBus on the arm and gripper position actuators."""

    def __init__(self, engine: Engine, config: ServoBusConfig, noise_counts: int, vin_mv: Callable[[], int]):
        self.engine = engine
        self.config = config
        self.noise = noise_counts
        self._vin_mv = vin_mv
        self._rng = np.random.default_rng([engine.config.seed, 2])
        m = engine.model
        self._servos: dict[int, _Servo] = {}
        for joint, calib in config.joints.items():
            act = engine.actuator(joint)
            s = _Servo(joint, calib, act, engine.joint_qpos(joint), float(m.actuator_gainprm[act, 0]))
            s.setpoint = s.start = s.target = float(engine.data.qpos[s.qpos])
            engine.data.ctrl[act] = s.setpoint
            self._servos[calib.id] = s
        engine.attach(self)

    # --- unit conversion ---------------------------------------------------------------
    def counts_to_rad(self, calib: ServoCalib, counts: float) -> float:
        return self.config.counts_to_rad(calib, counts)

    def rad_to_counts(self, calib: ServoCalib, rad: float) -> float:
        return self.config.rad_to_counts(calib, rad)

    def _servo(self, servo_id: int) -> _Servo:
        try:
            return self._servos[servo_id]
        except KeyError:
            raise DeviceError(f"servo id {servo_id}: no reply on the bus") from None

    # --- HAL: ServoBus -----------------------------------------------------------------
    def move(self, servo_id: int, position: int, duration_ms: int) -> None:
        s = self._servo(servo_id)
        if s.latched or not s.loaded:
            return
        lo, hi = (lim / self.config.centideg_per_count for lim in (s.calib.min, s.calib.max))
        counts = min(max(float(position), lo), hi) + s.offset
        s.start = float(self.engine.data.qpos[s.qpos])
        s.target = self.counts_to_rad(s.calib, counts)
        s.t0 = self.engine.time
        s.duration = max(0, min(int(duration_ms), 30000)) / 1000.0
        self._apply(s, s.t0)

    def read_position(self, servo_id: int) -> int:
        s = self._servo(servo_id)
        counts = self.rad_to_counts(s.calib, float(self.engine.data.qpos[s.qpos])) - s.offset
        if self.noise:
            counts += int(self._rng.integers(-self.noise, self.noise + 1))
        return int(round(counts))

    def read_status(self, servo_id: int) -> ServoStatus:
        s = self._servo(servo_id)
        return ServoStatus(self.read_position(servo_id), int(self._vin_mv()), 36, s.loaded)

    def set_load(self, servo_id: int, loaded: bool) -> None:
        s = self._servo(servo_id)
        if s.latched:
            return
        s.loaded = bool(loaded)
        here = float(self.engine.data.qpos[s.qpos])
        s.start = s.target = s.setpoint = here
        s.duration = 0.0
        self.engine.data.ctrl[s.act] = here  # re-loading holds where the joint sagged to
        self._set_gain(s, s.kp if loaded else 0.0)

    def adjust_offset(self, servo_id: int, offset: int) -> None:
        s = self._servo(servo_id)
        s.offset = int(max(-OFFSET_LIMIT, min(OFFSET_LIMIT, offset)))

    def read_offset(self, servo_id: int) -> int:
        return self._servo(servo_id).offset

    # --- faults ------------------------------------------------------------------------
    def joint(self, name: str) -> _Servo:
        for s in self._servos.values():
            if s.joint == name:
                return s
        raise KeyError(f"no servo for joint {name!r}")

    def unload(self, joint: str) -> None:
        self.set_load(self.joint(joint).calib.id, False)

    def latch(self, joint: str) -> None:
        self.joint(joint).latched = True

    def joint_position(self, joint: str) -> float:
        """Ground-truth joint angle, rad (for tests and the sim's own views)."""
        return float(self.engine.data.qpos[self.joint(joint).qpos])

    def place(self, positions: dict[str, float]) -> None:
        """Teleport joints to angles (scene set-up only, never used by the control stack)."""
        for name, rad in positions.items():
            s = self.joint(name)
            self.engine.data.qpos[s.qpos] = rad
            s.start = s.target = s.setpoint = rad
            s.duration = 0.0
            self.engine.data.ctrl[s.act] = rad

    # --- physics hook ------------------------------------------------------------------
    def _set_gain(self, s: _Servo, kp: float) -> None:
        m = self.engine.model
        m.actuator_gainprm[s.act, 0] = kp
        m.actuator_biasprm[s.act, 1] = -kp

    def _apply(self, s: _Servo, t: float) -> None:
        if s.duration <= 0 or t >= s.t0 + s.duration:
            s.setpoint = s.target
        else:
            s.setpoint = s.start + (s.target - s.start) * (t - s.t0) / s.duration
        self.engine.data.ctrl[s.act] = s.setpoint

    def pre_chunk(self, t: float) -> None:
        for s in self._servos.values():
            if s.loaded and s.setpoint != s.target:  # a finished ramp already holds its ctrl
                self._apply(s, t)
