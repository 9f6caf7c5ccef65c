"""Judging a simulated run from outside the stack: what reached the motors, where the robot
really was. Ground truth is read here only to judge, never fed back.

``MotionLog`` listens to the sim drivetrain's duty writes (one per control tick of the base
controller) and samples the true base pose at each. ``estop_figures`` turns it, with the
scripted presses, releases and resumes of the events file, into the issue's e-stop figures:

* ticks to zero duty: control ticks after a press until one writes all-zero duties (a tick at
  the press's own instant ran before the press, so it does not count);
* distance after press: the true path length from the press until the release (the coast);
* still until resume: between the release and the operator's resume (or the end of the run)
  every duty written is zero and the true base moves less than ``STILL_M``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mission.patrol import events_file as ev
from sim.backend import SimRobot

STILL_M = 0.005
"""True displacement allowed while 'still', m: physics settling of a stopped base, not motion."""


@dataclass
class MotionLog:
    sim: SimRobot
    t: list[float] = field(default_factory=list)
    duties: list[np.ndarray] = field(default_factory=list)
    xy: list[tuple[float, float]] = field(default_factory=list)

    def attach(self) -> "MotionLog":
        self.sim.drive.listeners.append(self._write)
        return self

    def _write(self, t: float, duties: np.ndarray) -> None:
        pose = self.sim.truth()
        self.t.append(t)
        self.duties.append(duties)
        self.xy.append((pose.x, pose.y))

    def after(self, start: float, end: float) -> slice:
        """Samples strictly after ``start`` up to ``end``."""
        t = np.asarray(self.t)
        return slice(int(np.searchsorted(t, start, side="right")), int(np.searchsorted(t, end, side="right")))

    def since(self, start: float, end: float) -> slice:
        """From the last sample at or before ``start`` (where the robot was then) up to ``end``."""
        s = self.after(start, end)
        return slice(max(s.start - 1, 0), s.stop)


@dataclass
class Press:
    at: float
    """Runtime time of the press."""
    released: float | None
    """When button and soft stop were both off again (None: never)."""
    resumed: float | None
    """The operator's first resume at or after the release (None: never)."""
    speed: float = 0.0
    """True base speed over the control tick before the press, m/s (was it driving?)."""
    ticks_to_zero: int | None = None
    """Control ticks from the press to all-zero duty (None: never within the run)."""
    distance_after: float = 0.0
    still_after_release: bool | None = None
    """No duty and no motion between release and resume (None: never released)."""
    moved_after_release: float = 0.0


def presses(events: list, t0: float) -> list[Press]:
    """Each engagement of the e-stop (button or soft) with its release and resume, from the
    events as scripted. An engagement while already engaged is part of the same press."""
    button = soft = False
    out: list[Press] = []
    for e in events:
        t = t0 + e.at
        was = button or soft
        if isinstance(e, ev.EStop):
            button = e.engaged
        elif isinstance(e, ev.SoftEStop):
            soft = e.engaged
        elif isinstance(e, ev.Resume) and out and out[-1].released is not None and out[-1].resumed is None:
            out[-1].resumed = t
        now = button or soft
        if now and not was:
            out.append(Press(t, None, None))
        elif was and not now:
            out[-1].released = t
    return out


def estop_figures(log: MotionLog, events: list, t0: float, end: float) -> list[Press]:
    found = presses(events, t0)
    for p in found:
        before = log.since(p.at, p.at)
        if before.start >= 1:
            i = before.start
            p.speed = math.dist(log.xy[i - 1], log.xy[i]) / max(log.t[i] - log.t[i - 1], 1e-9)
        after = log.after(p.at, end)
        zero = [i for i, d in enumerate(log.duties[after]) if not np.any(d)]
        p.ticks_to_zero = zero[0] + 1 if zero else None
        coast = log.since(p.at, p.released if p.released is not None else end)
        p.distance_after = _path_length(log.xy[coast])
        if p.released is not None:
            held = log.since(p.released, p.resumed if p.resumed is not None else end)
            xy = np.asarray(log.xy[held]).reshape(-1, 2)
            p.moved_after_release = float(np.max(np.hypot(*(xy - xy[0]).T))) if len(xy) else 0.0
            p.still_after_release = all(not np.any(d) for d in log.duties[held]) and p.moved_after_release < STILL_M
    return found


def _path_length(xy: list[tuple[float, float]]) -> float:
    return float(sum(math.dist(a, b) for a, b in zip(xy, xy[1:])))
