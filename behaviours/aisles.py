"""Before a leg, its aisles: ask for them, and until they are granted wait outside (or, told to
yield, back out of the aisle the robot is in); one leaf before each drive of a fleet's patrol.

The leaf plans the leg (the planner on the global costmap, as the navigator will), asks the
arbiter for every aisle on the way without waiting for the answer (the gate's
``ask``: it lands on Zenoh's thread and the leaf polls it on its ticks), and on a
refusal drives to where the gate says to wait and stays there, asking again every ``retry`` s
(a later refusal, planned from the wait, never moves it deeper). What to ask and
where to wait are the gate's (``mission.patrol.aisle_gate``, passed in: behaviours sit below
``mission``); this leaf only sequences it on the navigator. Waiting has no time limit of its own:
a robot that holds an aisle too long is the dispatcher's to report, a dead one's locks go with
its liveliness, and a wait that would deadlock is told to yield.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
import py_trees
from py_trees.common import Status

from hw.interfaces import Clock
from hw.odometry import Pose2D
from nav.navigator import Navigator, State
from nav.planner import PlanningError

ARRIVED = 0.15
"""Closer than this to where it should wait, m, the robot just waits (no goal for a step)."""


class EnterAisles(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, gate, nav: Navigator, goal: Callable[[], Pose2D], clock: Clock,
                 lengths_from: Callable[[tuple[float, float], np.ndarray], np.ndarray], retry: float):
        super().__init__(name)
        self.gate, self.nav, self.goal, self.clock = gate, nav, goal, clock
        self.lengths_from, self.retry = lengths_from, retry
        self._pending = self._moving = self._path = None
        self._want: list[int] = []
        self._next = -math.inf
        self._waiting = False
        self._refused_at: float | None = None
        self._yielded = False

    def initialise(self) -> None:
        self._pending = self._moving = self._path = None
        self._next = -math.inf
        self._waiting = self._yielded = False
        self._refused_at = None
        self.feedback_message = ""

    def update(self) -> Status:
        now = self.clock.now()
        if self._moving is not None:
            if self.nav.state in (State.FOLLOWING, State.RECOVERING):
                return Status.RUNNING
            if self._moving.back_out:  # out of its aisle (or as far as it got): it holds nothing now
                self.gate.backed_out()
            else:
                self._waiting = True
            self._moving = None
        if self._pending is None:
            return Status.RUNNING if now < self._next else self._ask()
        if not self._pending.answered.is_set():
            return Status.RUNNING
        here = self.nav.map_pose()
        v = self.gate.verdict(self._path, self._want, self._pending.answer,
                              lambda points: self.lengths_from((here.x, here.y), points))
        self._pending = None
        if v.go:
            self.feedback_message = ""
            self._wait_over(now)
            return Status.SUCCESS
        if self._refused_at is None:
            self._refused_at = now
        self._yielded |= v.back_out
        self._next = now + self.retry
        whose = ", ".join(f"{a} ({r})" for a, r in sorted((v.held_by or {}).items())) or "no answer"
        self.feedback_message = f"{'backing out for' if v.back_out else 'waiting outside'} aisles: {whose}"
        if v.back_out or not self._waiting:
            if math.hypot(v.to[0] - here.x, v.to[1] - here.y) > ARRIVED:
                self.nav.navigate_to(Pose2D(float(v.to[0]), float(v.to[1]), here.yaw), now, math.inf)
                self._moving = v
            elif v.back_out:
                self.gate.backed_out()
            else:
                self._waiting = True
        return Status.RUNNING

    def _ask(self) -> Status:
        if self.gate.asking:  # the gate's last request (a let-go) is still out: one at a time
            return Status.RUNNING
        here, goal = self.nav.map_pose(), self.goal()
        try:
            path = self.nav.planner.plan(self.nav.global_costmap.grid, (here.x, here.y), (goal.x, goal.y))
        except PlanningError:
            self._wait_over(self.clock.now())
            return Status.SUCCESS  # no way there: the drive fails on its own, with the planner's reason
        self._want = self.gate.want(path)
        if not self._want and not self.gate.held:
            self._wait_over(self.clock.now())
            return Status.SUCCESS  # no aisle on the way, none held: nothing to ask
        self._path, self._pending = path, self.gate.ask(self._want)
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self._moving is not None:
            self.nav.cancel(self.clock.now(), f"{self.name} stopped")
            self._moving = None
        if new_status is Status.INVALID:
            self._wait_over(self.clock.now())

    def _wait_over(self, now: float) -> None:
        """A wait ended: its seconds go to the gate (the report's ``aisles``)."""
        if self._refused_at is not None:
            self.gate.waited(now - self._refused_at, self._yielded)
            self._refused_at, self._yielded = None, False


class LetGoBehind(py_trees.behaviour.Behaviour):
    """Always RUNNING beside the patrol: every ``every`` s, the aisles the robot has left behind
    are let go (the gate's ``progress`` on the plan ahead of it; standing, on where it stands)."""

    def __init__(self, name: str, gate, nav: Navigator, clock: Clock, every: float):
        super().__init__(name)
        self.gate, self.nav, self.clock, self.every = gate, nav, clock, every
        self._next = -math.inf

    def update(self) -> Status:
        now = self.clock.now()
        if now >= self._next:
            self._next = now + self.every
            here = self.nav.map_pose()
            ahead = np.array([[here.x, here.y]])
            path = self.nav.path
            if self.nav.active and path is not None and len(path):
                nearest = int(np.argmin(np.hypot(path[:, 0] - here.x, path[:, 1] - here.y)))
                ahead = np.vstack([ahead, path[nearest:]])
            self.gate.progress(ahead)
        return Status.RUNNING
