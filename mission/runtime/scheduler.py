"""A rate scheduler: runs each subsystem at its own rate on the runtime clock.

The seed's robot is a set of loops at fixed beats (10 Hz controllers, 5 Hz e-stop publish,
10 Hz lidar, 20 Hz MPPI, ...). Here they are tasks; the scheduler asks the clock to wait until
the earliest one is due (on the sim clock that *advances physics* to that instant, on the wall
clock it sleeps) and then runs every task due at that instant in registration order.
Due times are kept in integer nanoseconds so two runs never drift apart through float error:
same seed, same order of events, same trajectory.
"""
from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field
from typing import Callable

from hw.interfaces import Clock

_NS = 1_000_000_000


@dataclass(order=True)
class _Task:
    due_ns: int
    order: int
    period_ns: int = field(compare=False)
    name: str = field(compare=False)
    fn: Callable[[float], None] = field(compare=False)
    active: bool = field(default=True, compare=False)


class Scheduler:
    """Periodic tasks on one clock. ``fn(now)`` gets the runtime time of its tick."""

    def __init__(self, clock: Clock):
        self.clock = clock
        self._heap: list[_Task] = []
        self._order = 0
        self._tasks: dict[str, _Task] = {}

    def every(self, name: str, rate_hz: float, fn: Callable[[float], None], *, offset: float = 0.0) -> None:
        """Run ``fn`` at ``rate_hz`` from ``now + offset``. Names are unique."""
        if rate_hz <= 0:
            raise ValueError(f"task {name!r}: rate must be positive, got {rate_hz}")
        if name in self._tasks:
            raise ValueError(f"task {name!r} is already scheduled")
        period = round(_NS / rate_hz)
        task = _Task(round((self.clock.now() + offset) * _NS), self._order, period, name, fn)
        self._order += 1
        self._tasks[name] = task
        heapq.heappush(self._heap, task)

    def at(self, name: str, t: float, fn: Callable[[float], None]) -> None:
        """Run ``fn`` once, at runtime time ``t`` (now, if ``t`` has passed). Tasks due at the
        same instant run in the order they were registered, one-shot or periodic."""
        if name in self._tasks:
            raise ValueError(f"task {name!r} is already scheduled")
        task = _Task(max(round(t * _NS), round(self.clock.now() * _NS)), self._order, 0, name, fn)
        self._order += 1
        self._tasks[name] = task
        heapq.heappush(self._heap, task)

    def cancel(self, name: str) -> None:
        task = self._tasks.pop(name, None)
        if task is not None:
            task.active = False

    @property
    def tasks(self) -> list[str]:
        return list(self._tasks)

    def next_due(self) -> float:
        """When the next task is due, runtime time (``inf`` with none): runtimes sharing one
        simulator step in lock-step by always stepping the one due first (``mission.jobs.fleet_sim``)."""
        while self._heap and not self._heap[0].active:
            heapq.heappop(self._heap)
        return self._heap[0].due_ns / _NS if self._heap else math.inf

    def run_until(self, t_end: float) -> None:
        """Run every task due up to and including ``t_end``, then bring the clock to ``t_end``."""
        end_ns = round(t_end * _NS)
        while self._heap and self._heap[0].due_ns <= end_ns:
            self.step()
        if self.clock.now() < t_end:
            self.clock.wait_until(t_end)

    def run_for(self, duration: float) -> None:
        self.run_until(self.clock.now() + duration)

    def step(self) -> float:
        """Wait for the earliest due instant and run every task due then. Returns that time."""
        while self._heap and not self._heap[0].active:
            heapq.heappop(self._heap)
        if not self._heap:
            raise RuntimeError("scheduler has no tasks")
        due_ns = self._heap[0].due_ns
        t = due_ns / _NS
        if self.clock.now() < t:
            self.clock.wait_until(t)
        while self._heap and self._heap[0].due_ns == due_ns:
            task = heapq.heappop(self._heap)
            if not task.active:
                continue
            task.fn(t)
            if not task.period_ns:  # one-shot: done
                self.cancel(task.name)
            elif task.active:
                task.due_ns += task.period_ns
                heapq.heappush(self._heap, task)
        return t
