"""The arm's trajectory controller: one 10 Hz beat from joint state to bus writes.

Each ``tick(now)`` (mission/runtime/scheduler.py calls it at the seed's 10 Hz controller rate):

1. read the joint state; the first complete one *pins* the live pose (nothing snaps to 0);
2. start a queued move (a preset or an IK pose) as one trajectory of all four joints, timed
   by the maximum joint speed, and sample it;
3. let the gripper goal decide reached / stalled;
4. watch for trips: shoulder_lift unloaded -> re-load and re-command; latched -> arm out of
   use and every subscriber told (the mission goes on without the arm); any joint still more
   than twice the dead-band off target a second after its command settled -> commanded to
   where it is, once (the stuck guard: stop pushing, which is what trips the servo);
5. re-assert through the dead-bands (``arm.servo_interface``);
6. park at ``home`` after the idle timeout (seed: never park the arm extended).

Commands are refused (``ArmUnavailable``) while there is no joint state yet, while calibrating,
after a latch, or while the relevant controller (``mirte_master_arm_controller``,
``mirte_master_gripper_controller``) is not active: the boot heal brings those up.
"""
from __future__ import annotations

import logging
from typing import Callable, Mapping, Sequence

import numpy as np

from arm import limits
from arm.config import ArmConfig
from arm.gripper import Gripper
from arm.presets import ARM_JOINTS, move_duration, preset
from arm.servo_interface import ServoInterface
from arm.stall import StallWatch, Verdict
from arm.trajectory import Trajectory
from hw.config import ServoBusConfig
from hw.controller_manager import ControllerManager
from hw.interfaces import ServoBus

ARM_CONTROLLER = "mirte_master_arm_controller"
GRIPPER_CONTROLLER = "mirte_master_gripper_controller"


class ArmUnavailable(RuntimeError):
    """The arm cannot take commands now; the message says why."""


class ArmController:
    def __init__(self, config: ArmConfig, servos: ServoBusConfig, bus: ServoBus,
                 controllers: ControllerManager | None = None, log: logging.Logger | None = None):
        self.config = config
        self.controllers = controllers
        self.log = log or logging.getLogger("lupin.arm")
        self.interface = ServoInterface(bus, servos, config.reassert, config.motion.max_joint_speed,
                                        (*ARM_JOINTS, Gripper.JOINT), self.log)
        self.gripper = Gripper(self.interface, config.gripper)
        self.stall = StallWatch(bus, self.interface, config.stall, config.reassert, self.log)
        self.trajectory: Trajectory | None = None
        self.fault: str | None = None
        self.suspended = False
        self._pending: tuple[np.ndarray, str] | None = None
        self._settled = dict.fromkeys(ARM_JOINTS, 0.0)
        self._move_start: dict[str, float | None] = dict.fromkeys(ARM_JOINTS)
        self._guarded = dict.fromkeys(ARM_JOINTS, False)
        self._last_command = 0.0
        self._subscribers: list[Callable[[str], None]] = []
        self.now = 0.0

    # --- who uses the arm ----------------------------------------------------------------
    @property
    def available(self) -> bool:
        return self.fault is None

    def subscribe(self, callback: Callable[[str], None]) -> None:
        """``callback(reason)`` once, when the arm is taken out of use (a latched servo)."""
        self._subscribers.append(callback)

    def positions(self) -> dict[str, float | None]:
        return {j: s.position for j, s in self.interface.slots.items()}

    def joint_vector(self) -> np.ndarray | None:
        q = [self.interface.position(j) for j in ARM_JOINTS]
        return None if any(v is None for v in q) else np.array(q)

    @property
    def moving(self) -> bool:
        return self._pending is not None or (self.trajectory is not None and not self.trajectory.done(self.now))

    def at(self, goal: Sequence[float] | Mapping[str, float], tol: float | None = None) -> bool:
        """All four joints within ``tol`` (default: the moved dead-band) of ``goal``."""
        q = self.joint_vector()
        g = np.array([goal[j] for j in ARM_JOINTS] if isinstance(goal, Mapping) else goal, dtype=float)
        tol = self.config.reassert.moved_deadband if tol is None else tol
        return q is not None and bool(np.all(np.abs(q - g) <= tol))

    # --- commands ------------------------------------------------------------------------
    def _check(self, controller: str) -> None:
        if self.fault is not None:
            raise ArmUnavailable(self.fault)
        if self.suspended:
            raise ArmUnavailable("arm is being calibrated")
        if not self.interface.pinned:
            raise ArmUnavailable("no complete joint state yet")
        if self.controllers is not None and not self.controllers.is_active(controller):
            raise ArmUnavailable(f"{controller} is {self.controllers.state(controller).value}, not active")

    def move_to(self, goal: Sequence[float] | Mapping[str, float], label: str = "") -> np.ndarray:
        """Queue one trajectory of all four joints to ``goal`` (clamped into the windows);
        it starts on the next tick. Returns the clamped goal."""
        self._check(ARM_CONTROLLER)
        q = [goal[j] for j in ARM_JOINTS] if isinstance(goal, Mapping) else list(goal)
        if len(q) != len(ARM_JOINTS):
            raise ValueError(f"an arm goal has {len(ARM_JOINTS)} joints ({', '.join(ARM_JOINTS)}), got {len(q)}")
        target = limits.clamp_arm(q)
        self._pending = (target, label)
        self._last_command = self.now
        return target

    def preset(self, name: str) -> np.ndarray:
        """Move to a named preset (``UnknownPreset`` for a name that does not exist)."""
        return self.move_to(preset(name), label=name)

    def grip(self, deg: float) -> float:
        """Gripper goal in operator degrees (-30 OPEN .. +30 CLOSED); see ``gripper.result``."""
        self._check(GRIPPER_CONTROLLER)
        self._last_command = self.now
        return self.gripper.angle(deg)

    def suspend(self) -> None:
        """Stop driving the bus (calibration unloads the servos and poses the arm by hand)."""
        self.suspended = True
        self.trajectory, self._pending = None, None

    def resume(self) -> None:
        """Drive again from the live pose: re-pin on the next complete joint state."""
        self.suspended = False
        self.interface.pinned = False

    # --- the beat ------------------------------------------------------------------------
    def tick(self, now: float) -> None:
        self.now = now
        if self.fault is not None or self.suspended:
            return
        was_pinned = self.interface.pinned
        self.interface.read(now)
        if not self.interface.pinned:
            return
        if not was_pinned:
            self._last_command = now
            for j in ARM_JOINTS:
                self._settled[j], self._move_start[j] = now, self.interface.position(j)
        self._start_pending(now)
        if self.trajectory is not None:
            self._sample(now)
            self._last_command = now  # idle counts from the end of the last move
        self.gripper.tick(now)
        if not self._watch(now):
            return
        self.interface.write()
        self._idle_park(now)

    def _start_pending(self, now: float) -> None:
        if self._pending is None:
            return
        goal, label = self._pending
        self._pending = None
        start = np.array([self.interface.command(j) for j in ARM_JOINTS])
        cfg = self.config.motion
        self.trajectory = Trajectory(start, goal, now, move_duration(start, goal, cfg.max_joint_speed, cfg.min_duration), label)
        for j in ARM_JOINTS:
            self._move_start[j] = self.interface.position(j)
            self._guarded[j] = False

    def _sample(self, now: float) -> None:
        q = self.trajectory.sample(now)
        for j, v in zip(ARM_JOINTS, q):
            if v != self.interface.command(j):
                self.interface.set_command(j, float(v))
                self._settled[j] = now
        if self.trajectory.done(now):
            # The final point is always sent for a joint that moved more than the command
            # dead-band, so a slow joint ends on its goal and not on its last sample sent.
            tr, db = self.trajectory, self.config.reassert.command_deadband
            for j, a, b in zip(ARM_JOINTS, tr.start, tr.goal):
                if abs(b - a) > db and self.interface.slots[j].sent != self.interface.command(j):
                    self.interface.resend(j)
            self.trajectory = None

    def _watch(self, now: float) -> bool:
        """Stall and stuck handling; False when the arm has just been taken out of use."""
        cfg = self.config.reassert
        for j in ARM_JOINTS:
            s = self.interface.slots[j]
            if s.position is None or s.command is None:
                continue
            off = abs(s.position - s.command)
            if off <= cfg.moved_deadband:
                self.stall.settled(j)
            changed, drifted = self.interface.due(j)
            quiet = now - max(self._settled[j], s.settle_until) >= cfg.stuck_after  # commanded, sent, ramped
            stuck = (off > cfg.stuck_factor * cfg.moved_deadband and quiet and not (changed or drifted)
                     and not self._guarded[j])
            if self.stall.watches(j) and ((drifted and not changed) or stuck):
                verdict = self.stall.inspect(j, stuck, self._move_start[j])
                if verdict is Verdict.LATCHED:
                    self._take_out_of_use(self.stall.reason)
                    return False
                if verdict is Verdict.RELOADED:
                    self._settled[j], self._move_start[j] = now, s.position
                    continue
            if stuck:
                self.log.warning("%s stuck %.3f rad off target: holding where it is", j, off)
                self.interface.set_command(j, s.position)
                self._guarded[j] = True
        return True

    def _take_out_of_use(self, reason: str) -> None:
        self.fault = reason
        self.trajectory, self._pending = None, None
        for callback in self._subscribers:
            callback(reason)

    def _idle_park(self, now: float) -> None:
        if self.moving or now - self._last_command < self.config.motion.idle_timeout:
            return
        if self.controllers is not None and not self.controllers.is_active(ARM_CONTROLLER):
            return
        self._last_command = now
        if not self.at(preset("home")):
            self.log.info("arm idle for %.0f s: parking at home", self.config.motion.idle_timeout)
            self._pending = (limits.clamp_arm(list(preset("home").values())), "home")
