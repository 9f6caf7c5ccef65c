"""The gripper command path: operator degrees -> URDF radians -> the gripper controller.

Seed ("Gripper command path"): HMI and voice gripper commands never call the raw Hiwonder
servo service. The bridge clamps and maps the operator's angle onto the URDF [-0.20, 0.25] rad
range through the shared limits module and sends a GripperCommand goal to the gripper
controller; a raw write would fight the controller and the dead-band would snap the jaw back.
Here the goal becomes the gripper joint's command in the same write loop as the arm (the seed's
surprise: the gripper shares the arm's hardware interface), and the goal ends like a
GripperActionController goal: *reached* within tolerance, or *stalled* when the jaw stops
short (an object in the jaw, or a servo that does not answer its commands).
"""
from __future__ import annotations

from enum import Enum

from arm import limits
from arm.config import GripperConfig
from arm.servo_interface import ServoInterface


class GripperResult(str, Enum):
    MOVING = "moving"
    REACHED = "reached"
    STALLED = "stalled"


class Gripper:
    JOINT = "gripper"

    def __init__(self, interface: ServoInterface, config: GripperConfig):
        self.interface = interface
        self.config = config
        self.goal: float | None = None
        self.result: GripperResult | None = None
        self._ref: float | None = None
        self._since: float | None = None

    def open(self) -> float:
        return self.angle(limits.GRIPPER_OPEN_DEG)

    def close(self) -> float:
        return self.angle(limits.GRIPPER_CLOSED_DEG)

    def angle(self, deg: float) -> float:
        """Send a goal in operator degrees (-30 OPEN .. +30 CLOSED, clamped); returns the
        goal in URDF radians. The result is MOVING until ``tick`` decides."""
        self.goal = limits.gripper_deg_to_rad(deg)
        self.interface.set_command(self.JOINT, self.goal)
        self.result = GripperResult.MOVING
        self._ref, self._since = self.interface.position(self.JOINT), None
        return self.goal

    def tick(self, now: float) -> None:
        if self.result is not GripperResult.MOVING:
            return
        pos = self.interface.position(self.JOINT)
        if pos is None:
            return
        if self._since is None:
            self._since = now
        if abs(pos - self.goal) <= self.config.goal_tolerance:
            self.result = GripperResult.REACHED
            return
        if self._ref is None or abs(pos - self._ref) > self.config.stall_velocity * self.config.stall_timeout:
            self._ref, self._since = pos, now  # still moving: restart the stall clock
        elif now - self._since >= self.config.stall_timeout:
            self.result = GripperResult.STALLED
