"""Move the arm to a goal (a preset or an aimed pose) and wait until it is there.

The goal is a callable read in ``initialise``, so the tree can choose ``inspect`` or an IK
aim from where the robot actually stopped. FAILURE, with the controller's reason, when the arm
refuses the command (``ArmUnavailable``: latched servo, inactive controller) or is taken out
of use while moving. ``terminate(INVALID)`` holds the arm where it is.
"""
from __future__ import annotations

from typing import Callable, Mapping

import numpy as np
import py_trees
from py_trees.common import Status

from arm.controller import ArmController, ArmUnavailable
from arm.presets import ARM_JOINTS

Goal = Callable[[], tuple[np.ndarray | Mapping[str, float], str]]
"""A joint goal (vector in joint order, or joint name -> angle) and its label."""


class MoveArm(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, arm: ArmController, goal: Goal):
        super().__init__(name)
        self.arm, self.goal = arm, goal
        self.target: np.ndarray | None = None

    def initialise(self) -> None:
        self.feedback_message, self.target = "", None
        goal, label = self.goal()
        try:
            self.target = self.arm.move_to(goal, label)
        except ArmUnavailable as exc:
            self.feedback_message = f"arm unavailable: {exc}"

    def update(self) -> Status:
        if self.target is None:
            return Status.FAILURE
        if not self.arm.available:
            self.feedback_message = f"arm unavailable: {self.arm.fault}"
            return Status.FAILURE
        if not self.arm.moving and self.arm.at(self.target):
            return Status.SUCCESS
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self.target is not None and self.arm.moving:
            q = self.arm.joint_vector()
            if q is not None and self.arm.available:
                self.arm.move_to(dict(zip(ARM_JOINTS, q)), "hold")
