"""Operator-in-the-loop Hiwonder zero-offset calibration: start | commit | cancel | status.

Seed (arm_calibrate_server): ``start`` disables the servos so the operator can hand-pose the
arm at its zero (the URDF zero: every link straight up, the jaw at 0); ``commit`` samples each
servo's raw count for ~2 s and writes per-joint offsets, with a noise-floor gate (a joint still
moving under the operator's hand, or a noisy encoder, is rejected) and a small safety clamp
that *skips* a servo needing more (a horn on the wrong spline is a misassembly no offset should
hide). shoulder_pan is deliberately omitted. Writing is the Hiwonder pair ANGLE_OFFSET_ADJUST
(17, takes effect at once) then ANGLE_OFFSET_WRITE (18, persists it).

Hardware only: the sim's servo bus has no ANGLE_OFFSET_WRITE (the seed: "the underlying
Hiwonder bus services don't exist in sim"), and ``Calibration`` refuses such a bus with one
clear message. Sampling runs on ``tick(now)`` at the controller beat, so nothing here sleeps.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from enum import Enum
from typing import Protocol, runtime_checkable

import numpy as np

from arm.config import CalibrationConfig
from hw.config import ServoBusConfig
from hw.errors import InputError
from hw.interfaces import DeviceError, ServoBus

OFFSET_RANGE = 125  # ANGLE_OFFSET_ADJUST: -125..125 units = +-30 deg (hardware reference)


@runtime_checkable
class OffsetBus(ServoBus, Protocol):
    """A servo bus that can persist offsets (the real Hiwonder driver)."""

    def write_offset(self, servo_id: int) -> None: ...


class CalibrationError(InputError):
    """A calibration call that cannot be honoured (wrong backend, wrong moment)."""


class Phase(str, Enum):
    IDLE = "idle"
    POSING = "posing"
    SAMPLING = "sampling"


@dataclass
class JointOutcome:
    joint: str
    status: str  # written | noisy | misassembled | unreadable
    offset: int | None = None
    detail: str = ""


@dataclass
class CalibrationStatus:
    phase: Phase
    joints: tuple[str, ...]
    outcomes: list[JointOutcome] = field(default_factory=list)
    note: str = ""


class Calibration:
    def __init__(self, bus: ServoBus, servos: ServoBusConfig, config: CalibrationConfig,
                 arm=None, log: logging.Logger | None = None):
        """``arm``: the ArmController to suspend while the operator poses the arm."""
        if not isinstance(bus, OffsetBus):
            raise CalibrationError("arm calibration is hardware only: this servo bus (the sim's) has no "
                                   "ANGLE_OFFSET_WRITE to persist offsets; run it with --backend hw")
        self.bus = bus
        self.servos = servos
        self.config = config
        self.arm = arm
        self.log = log or logging.getLogger("lupin.arm")
        self.phase = Phase.IDLE
        self.outcomes: list[JointOutcome] = []
        self.note = ""
        self._samples: dict[str, list[int]] = {}
        self._until = 0.0

    def _ids(self):
        return [(j, self.servos.joints[j].id) for j in self.config.joints]

    # --- the four actions ----------------------------------------------------------------
    def start(self) -> CalibrationStatus:
        if self.phase is not Phase.IDLE:
            raise CalibrationError(f"calibration already {self.phase.value}; commit or cancel it first")
        if self.arm is not None:
            self.arm.suspend()
        for joint, sid in self._ids():
            self.bus.set_load(sid, False)
        self.phase, self.outcomes = Phase.POSING, []
        self.note = "servos unloaded: pose the arm at its zero, then commit"
        return self.status()

    def commit(self, now: float) -> CalibrationStatus:
        if self.phase is not Phase.POSING:
            raise CalibrationError(f"nothing to commit: calibration is {self.phase.value} (start it first)")
        self.phase = Phase.SAMPLING
        self._samples = {j: [] for j in self.config.joints}
        self._until = now + self.config.sample_duration
        self.note = f"sampling for {self.config.sample_duration:g} s: keep still"
        return self.status()

    def cancel(self) -> CalibrationStatus:
        if self.phase is not Phase.IDLE:
            self._finish("cancelled: no offsets written")
        return self.status()

    def status(self) -> CalibrationStatus:
        return CalibrationStatus(self.phase, tuple(self.config.joints), list(self.outcomes), self.note)

    def tick(self, now: float) -> None:
        if self.phase is not Phase.SAMPLING:
            return
        for joint, sid in self._ids():
            try:
                self._samples[joint].append(int(self.bus.read_position(sid)))
            except (DeviceError, ValueError, TypeError):
                pass
        if now >= self._until:
            self.outcomes = [self._calibrate(joint, sid) for joint, sid in self._ids()]
            written = sum(o.status == "written" for o in self.outcomes)
            self._finish(f"committed: {written} of {len(self.outcomes)} offsets written")

    # --- internals -----------------------------------------------------------------------
    def _calibrate(self, joint: str, sid: int) -> JointOutcome:
        samples = np.asarray(self._samples[joint], dtype=float)
        if samples.size < 3:
            return JointOutcome(joint, "unreadable", detail=f"{samples.size} readings")
        spread = float(samples.std())
        if spread > self.config.noise_floor_counts:
            return JointOutcome(joint, "noisy", detail=f"spread {spread:.1f} counts > {self.config.noise_floor_counts:g}")
        try:
            current = int(self.bus.read_offset(sid))
            physical = float(samples.mean()) + current  # reads are shifted by the offset in use
            zero = self.servos.joints[joint].home / self.servos.centideg_per_count
            offset = int(round(physical - zero))
            limit = min(self.config.max_offset_counts, OFFSET_RANGE)
            if abs(offset) > limit:
                return JointOutcome(joint, "misassembled", offset,
                                    f"needs {offset} counts, safe limit +-{limit}: check the horn")
            self.bus.adjust_offset(sid, offset)
            self.bus.write_offset(sid)
        except DeviceError as exc:
            return JointOutcome(joint, "unreadable", detail=str(exc))
        self.log.info("calibrated %s: offset %d counts (%.2f deg)", joint, offset, offset * self.servos.centideg_per_count / 100)
        return JointOutcome(joint, "written", offset)

    def _finish(self, note: str) -> None:
        for joint, sid in self._ids():
            try:
                self.bus.set_load(sid, True)
            except DeviceError as exc:
                self.log.warning("%s: re-load after calibration failed: %s", joint, exc)
        self.phase, self.note = Phase.IDLE, note
        if self.arm is not None:
            self.arm.resume()
