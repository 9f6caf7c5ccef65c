"""A timeout on the runtime clock: the decorator py_trees' own ``Timeout`` would be, minus wall time.

py_trees' ``decorators.Timeout`` measures ``time.monotonic()``; in the sim the runtime clock runs
several times faster than the wall, so a 60 s navigation attempt would be cut at 60 *wall*
seconds (minutes of robot time) and runs would stop being repeatable for a seed. This one reads
the clock the scheduler ticks the tree on (DESIGN.md: nothing in the core reads wall time).

On expiry the child is stopped with ``INVALID`` (its ``terminate`` cancels what it started: the
navigation goal, the arm move) and the decorator fails, with the child's name in its feedback,
so a ``Retry`` above it starts a fresh attempt.

``paused`` says how many seconds of the child's run do not count against it: a drive's waits for
people (``Navigator.held_for``). A cart pusher pacing the aisle a pot stands in held the robot
waiting for 40 of a drive's 60 s, and the drive was cut 0.15 m short of the approach pose as the
aisle came free (safety.people seed 1, 308 s; the aisle's six pots were lost). The navigator
bounds those waits itself (``person_wait``, ``blocked_wait``), so an attempt still ends.
"""
from __future__ import annotations

import py_trees
from py_trees.common import Status

from typing import Callable

from hw.interfaces import Clock


class Timeout(py_trees.decorators.Decorator):
    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, clock: Clock, duration: float,
                 paused: Callable[[], float] = lambda: 0.0):
        super().__init__(name=name, child=child)
        self.clock, self.duration, self.paused = clock, duration, paused
        self.deadline = 0.0

    def initialise(self) -> None:
        self.deadline = self.clock.now() + self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        status = self.decorated.status
        if status in (Status.SUCCESS, Status.FAILURE):
            self.feedback_message = self.decorated.feedback_message
            return status
        if self.clock.now() >= self.deadline + self.paused():
            self.decorated.stop(Status.INVALID)
            waited = self.paused()
            self.feedback_message = (f"{self.decorated.name}: timed out after {self.duration:g} s"
                                     + (f" and {waited:.0f} s of waiting" if waited >= 0.5 else ""))
            return Status.FAILURE
        return Status.RUNNING
