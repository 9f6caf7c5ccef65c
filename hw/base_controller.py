"""The base controller: mux twist -> mecanum IK -> wheel PID -> PWM duties, plus odometry.

One ``tick(now)`` is one beat of the seed's controller_manager (``update_rate: 10``, so every
command on this robot is a 100 ms beat). Each tick, in this order:

1. read the encoders (apply ``encoder_signs``) and turn the tick delta into wheel speeds,
   ``dticks / ticks_per_rev * 2 pi / dt`` (the first tick only primes the counters), and feed
   them to the wheel odometry (``/mirte_base_controller/odom`` in the seed);
2. take the twist_mux output, the only path from any velocity source to the wheels, through
   the collision monitor (``hw.collision_monitor``: scaled or stopped for what the lidar sees
   right now, whichever source sent it);
3. if the e-stop is engaged (read *now*, not the 5 Hz published state) or either stage of the
   seed's base chain (``pid_wheels_controller``, ``mirte_base_controller``) is not active, write
   all-zero duties and reset the PID: the wheels stop on the same tick the press is seen, and an
   integrator charged before the stop cannot kick the robot on release; while the e-stop holds,
   every twist on the mux is voided (``TwistMux.discard_until``), so none sent before the
   release drives the base after it;
4. otherwise mecanum IK -> per-wheel PID -> ``duty = command / max_wheel_speed`` clipped to
   [-1, 1] and lifted past the motor dead-zone (``duty_dead_zone``) where the wheel is meant to
   turn, times ``motor_signs``, written to the wheel driver.

Wheel references that exceed ``max_wheel_speed`` are scaled down together (desaturation), so a
fast diagonal command keeps its direction and slows down instead of curving as one wheel clips.

Device faults degrade, they do not crash (``hw.interfaces.DeviceError``): an unreadable encoder
means the loop cannot be closed, so the wheels are stopped until readings return; a failed duty
write is logged and retried on the next tick.
"""
from __future__ import annotations

import logging
import math
from typing import Protocol

import numpy as np

from hw.config import BaseConfig
from hw.controller_manager import ControllerManager
from hw.estop import EStopBridge
from hw.interfaces import ZERO_TWIST, DeviceError, Twist, WheelDriver, WheelEncoders
from hw.mecanum import Mecanum
from hw.odometry import WheelOdometry
from hw.pid import Pid
from hw.twist_mux import TwistMux

class TwistGuard(Protocol):
    def filter(self, twist: Twist, now: float) -> Twist: ...


#: Both stages of the seed's base chain must be active for the wheels to move.
REQUIRED_CONTROLLERS: tuple[str, ...] = ("pid_wheels_controller", "mirte_base_controller")

#: ``source`` reported when the base is held stopped rather than following the mux.
STOPPED_ESTOP = "estop"
STOPPED_INACTIVE = "controllers_inactive"
STOPPED_ENCODER_FAULT = "encoder_fault"


class BaseController:
    def __init__(
        self,
        config: BaseConfig,
        wheels: WheelDriver,
        encoders: WheelEncoders,
        mux: TwistMux,
        estop: EStopBridge,
        controllers: ControllerManager,
        log: logging.Logger | None = None,
        guard: "TwistGuard | None" = None,
    ):
        self.config = config
        self.wheels = wheels
        self.encoders = encoders
        self.mux = mux
        self.estop = estop
        self.controllers = controllers
        self.guard = guard
        """The collision monitor (None: the mux's twist goes to the wheels as it is)."""
        self.log = log if log is not None else logging.getLogger(__name__)

        self.mecanum = Mecanum.from_config(config)
        self.pid = Pid(config.pid, output_limit=config.max_wheel_speed)
        self.odometry = WheelOdometry(self.mecanum)
        self._encoder_signs = np.asarray(config.encoder_signs, dtype=np.int64)
        self._motor_signs = np.asarray(config.motor_signs, dtype=float)
        self._rad_per_tick = 2.0 * math.pi / config.ticks_per_rev

        self.wheel_speeds = np.zeros(4)
        """Measured wheel angular velocities, rad/s, WHEELS order (mean over the last beat)."""
        self.reference = np.zeros(4)
        """Wheel speed references from the mecanum IK, rad/s (zero while stopped)."""
        self.last_duties = np.zeros(4)
        """The duty vector written on the last tick (after motor_signs)."""
        self.command: Twist = ZERO_TWIST
        """The body twist in use this tick (zero while stopped)."""
        self.source: str = STOPPED_INACTIVE
        """Who owns the wheels: a mux source name, 'idle', or a STOPPED_* reason."""

        self._prev_ticks: np.ndarray | None = None
        self._prev_t: float | None = None
        self._last_dt: float | None = None
        self._encoder_failing = False
        self._write_failing = False

    @property
    def period(self) -> float:
        return 1.0 / self.config.control_rate

    def driving(self) -> bool:
        """Are the wheels told to turn (a non-zero reference this beat)? A robot held, or pushed
        along by someone while told to stand, is not driving."""
        return bool(np.any(self.reference != 0.0))

    def tick(self, now: float) -> np.ndarray:
        """One control beat at time ``now``; returns the duties written."""
        measured_ok = self._measure(now)
        twist, source = self.mux.select(now)

        if self.estop.engaged():
            stop_reason = STOPPED_ESTOP
            self.mux.discard_until(now)  # what was sent before the release never drives after it
        elif not all(self.controllers.is_active(n) for n in REQUIRED_CONTROLLERS):
            stop_reason = STOPPED_INACTIVE
        elif not measured_ok:
            stop_reason = STOPPED_ENCODER_FAULT
        else:
            stop_reason = None

        if stop_reason is not None:
            self.pid.reset()
            self.command = ZERO_TWIST
            self.source = stop_reason
            self.reference = np.zeros(4)
            duties = np.zeros(4)
        else:
            if self.guard is not None:
                twist = self.guard.filter(twist, now)
            self.command = twist
            self.source = source
            self.reference = self._desaturate(self.mecanum.inverse(twist))
            dt = self._last_dt if self._last_dt is not None else self.period
            out = self.pid.update(self.reference, self.wheel_speeds, dt)
            duties = self._duty(out, self.reference) * self._motor_signs

        self._write(duties)
        return self.last_duties

    # -- the pieces of a tick ------------------------------------------------------------------

    def _measure(self, now: float) -> bool:
        """Read encoders, update wheel speeds and odometry. False when the read failed."""
        try:
            raw = self.encoders.read_ticks()
        except (DeviceError, OSError) as exc:
            if not self._encoder_failing:
                self.log.error("wheel encoders unreadable (%s): stopping the base", exc)
                self._encoder_failing = True
            self._prev_ticks, self._prev_t, self._last_dt = None, None, None
            self.wheel_speeds = np.zeros(4)
            return False
        if self._encoder_failing:
            self.log.warning("wheel encoders readable again")
            self._encoder_failing = False

        ticks = np.asarray(raw, dtype=np.int64) * self._encoder_signs
        if self._prev_ticks is None:
            self.wheel_speeds = np.zeros(4)
            self._last_dt = None
        else:
            dt = now - self._prev_t
            if dt > 0:
                self.wheel_speeds = (ticks - self._prev_ticks) * self._rad_per_tick / dt
                self.odometry.update(self.wheel_speeds, dt)
                self._last_dt = dt
        self._prev_ticks, self._prev_t = ticks, now
        return True

    def _duty(self, out: np.ndarray, reference: np.ndarray) -> np.ndarray:
        """Wheel command (rad/s) -> duty in [-1, 1], mapped past the motor dead-zone wherever
        the wheel is meant to turn (a zero reference keeps a plain, stop-friendly map)."""
        raw = np.clip(out / self.config.max_wheel_speed, -1.0, 1.0)
        dz = self.config.duty_dead_zone
        lifted = np.sign(raw) * (dz + np.abs(raw) * (1.0 - dz))
        return np.where((reference != 0.0) & (raw != 0.0), lifted, raw)

    def _desaturate(self, reference: np.ndarray) -> np.ndarray:
        peak = float(np.max(np.abs(reference)))
        limit = self.config.max_wheel_speed
        return reference * (limit / peak) if peak > limit else reference

    def _write(self, duties: np.ndarray) -> None:
        self.last_duties = duties
        try:
            self.wheels.set_duties([float(d) for d in duties])
        except (DeviceError, OSError) as exc:
            if not self._write_failing:
                self.log.error("wheel driver write failed (%s): retrying every tick", exc)
                self._write_failing = True
            return
        self._write_failing = False
