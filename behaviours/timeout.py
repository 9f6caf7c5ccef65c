"""A timeout on the runtime clock: the decorator py_trees' own ``Timeout`` would be, minus wall time.

py_trees' ``decorators.Timeout`` measures ``time.monotonic()``; in the sim the runtime clock runs
several times faster than the wall, so a 60 s navigation attempt would be cut at 60 *wall*
seconds (minutes of robot time) and runs would stop being repeatable for a seed. This one reads
the clock the scheduler ticks the tree on (DESIGN.md: nothing in the core reads wall time).

On expiry the child is stopped with ``INVALID`` (its ``terminate`` cancels what it started: the
navigation goal, the arm move) and the decorator fails, with the child's name in its feedback,
so a ``Retry`` above it starts a fresh attempt.

``paused``, when given, stops the clock while it says so: a drive's limit is on driving, and
while the navigator waits for a person (its own ``person_wait`` bounds that) the attempt's
minute is not spent. Counted through such waits, a grower working a minute on the approach
pose ended the attempt the moment they left (safety.people seed 1 at 130 s: "approach P36
stopped after 60.0 s", 35 s of it waiting).
"""
from __future__ import annotations

import py_trees
from py_trees.common import Status

from typing import Callable

from hw.interfaces import Clock


class Timeout(py_trees.decorators.Decorator):
    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, clock: Clock, duration: float,
                 paused: Callable[[], bool] | None = None):
        super().__init__(name=name, child=child)
        self.clock, self.duration, self.paused = clock, duration, paused
        self.deadline = self._last = 0.0

    def initialise(self) -> None:
        self.deadline = self._last = self.clock.now()
        self.deadline += self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        status = self.decorated.status
        if status in (Status.SUCCESS, Status.FAILURE):
            self.feedback_message = self.decorated.feedback_message
            return status
        now, last, self._last = self.clock.now(), self._last, self.clock.now()
        if self.paused is not None and self.paused():
            self.deadline += now - last
        if now >= self.deadline:
            self.decorated.stop(Status.INVALID)
            self.feedback_message = f"{self.decorated.name}: timed out after {self.duration:g} s"
            return Status.FAILURE
        return Status.RUNNING
