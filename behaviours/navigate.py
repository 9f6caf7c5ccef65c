"""Drive to a map-frame pose through the navigator: one attempt per run of the leaf.

``initialise`` hands the goal to the navigator (the goal is a callable, read when the attempt
starts, so a retry re-reads it); ``update`` mirrors the navigator's state; ``terminate(INVALID)``
(a timeout above it, an abort, the e-stop or pause guard) cancels the goal, so the
``auto`` source stops publishing and the mux lets the wheels stop; only while the leaf runs: a
finished leaf that a selector clears later (py_trees stops the children before the one it
remembers) would cancel the goal of whichever leaf drives now (a pot's look beside its taken
approach pose, given up the moment it was set). The attempt's time limit is
the ``Timeout`` decorator's, not the navigator's: the goal is given with no deadline of its own.
"""
from __future__ import annotations

import math
from typing import Callable

import py_trees
from py_trees.common import Status

from hw.interfaces import Clock
from hw.odometry import Pose2D
from nav.navigator import Navigator, State


class NavigateTo(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, nav: Navigator, goal: Callable[[], Pose2D], clock: Clock,
                 on_start: Callable[[], None] = lambda: None, xy_tolerance: float | None = None):
        super().__init__(name)
        self.nav, self.goal, self.clock, self.on_start = nav, goal, clock, on_start
        self.xy_tolerance = xy_tolerance
        """A tighter goal tolerance than the navigator's, when the goal asks for one."""

    def initialise(self) -> None:
        self.on_start()
        self.feedback_message = ""
        self.nav.navigate_to(self.goal(), self.clock.now(), math.inf, self.xy_tolerance)

    def update(self) -> Status:
        state = self.nav.state
        if state is State.SUCCEEDED:
            return Status.SUCCESS
        if state in (State.FAILED, State.CANCELED):
            self.feedback_message = f"navigation {state.value}: {self.nav.reason}"
            return Status.FAILURE
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self.status is Status.RUNNING:
            self.nav.cancel(self.clock.now(), f"{self.name} stopped")
