"""A timeout on the runtime clock: the decorator py_trees' own ``Timeout`` would be, minus wall time.

py_trees' ``decorators.Timeout`` measures ``time.monotonic()``; in the sim the runtime clock runs
several times faster than the wall, so a 60 s navigation attempt would be cut at 60 *wall*
seconds (minutes of robot time) and runs would stop being repeatable for a seed. This one reads
the clock the scheduler ticks the tree on (DESIGN.md: nothing in the core reads wall time).

On expiry the child is stopped with ``INVALID`` (its ``terminate`` cancels what it started: the
navigation goal, the arm move) and the decorator fails, with the child's name in its feedback,
so a ``Retry`` above it starts a fresh attempt.
"""
from __future__ import annotations

import py_trees
from py_trees.common import Status

from hw.interfaces import Clock


class Timeout(py_trees.decorators.Decorator):
    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, clock: Clock, duration: float):
        super().__init__(name=name, child=child)
        self.clock, self.duration = clock, duration
        self.deadline = 0.0

    def initialise(self) -> None:
        self.deadline = self.clock.now() + self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        status = self.decorated.status
        if status in (Status.SUCCESS, Status.FAILURE):
            self.feedback_message = self.decorated.feedback_message
            return status
        if self.clock.now() >= self.deadline:
            self.decorated.stop(Status.INVALID)
            self.feedback_message = f"{self.decorated.name}: timed out after {self.duration:g} s"
            return Status.FAILURE
        return Status.RUNNING
