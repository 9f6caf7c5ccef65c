"""The scenario judge's e-stop figures, from outside the stack: what reached the motors, where
the robot really was (``mission.scenario.motion_log``), at the instants the events really fired.

``estop_figures`` turns the log, with the presses, releases and resumes as they fired, into the
issue's e-stop figures:

* speed at press: the true base speed over the control tick up to the press (was it driving? a
  press at rest tests nothing);
* ticks to zero duty: control ticks after a press until one writes all-zero duties (a tick at
  the press's own instant ran before the press, so it does not count);
* distance after press: the true path length from the press until the release (the coast);
* still until resume: between the release and the operator's resume (or the end of the run)
  every duty written is zero and the true base moves less than ``STILL_M``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mission.patrol import events_file as ev
from mission.scenario.motion_log import MotionLog

STILL_M = 0.005
"""True displacement allowed while 'still', m: physics settling of a stopped base, not motion."""


@dataclass
class Press:
    at: float
    """Runtime time of the press."""
    released: float | None
    """When button and soft stop were both off again (None: never)."""
    resumed: float | None
    """The operator's first resume at or after the release (None: never)."""
    speed: float = 0.0
    """True base speed over the control tick up to the press, m/s (was it driving?)."""
    ticks_to_zero: int | None = None
    """Control ticks from the press to all-zero duty (None: never within the run)."""
    distance_after: float = 0.0
    still_after_release: bool | None = None
    """No duty and no motion between release and resume (None: never released)."""
    moved_after_release: float = 0.0


def presses(events: list, fired: dict[int, float]) -> list[Press]:
    """Each engagement of the e-stop (button or soft) with its release and resume, from the
    events as they fired (``fired``: runtime time by event index; one never fired did nothing).
    An engagement while already engaged is part of the same press."""
    button = soft = False
    out: list[Press] = []
    for i in sorted(fired, key=lambda i: (fired[i], i)):
        e, t = events[i], fired[i]
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


def estop_figures(log: MotionLog, events: list, fired: dict[int, float], end: float) -> list[Press]:
    found, xy = presses(events, fired), log.xy
    for p in found:
        p.speed = log.speed_at(p.at)
        after = log.after(p.at, end)
        zero = [i for i, d in enumerate(log.duties[after]) if not np.any(d)]
        p.ticks_to_zero = zero[0] + 1 if zero else None
        coast = log.since(p.at, p.released if p.released is not None else end)
        p.distance_after = path_length(xy[coast])
        if p.released is not None:
            held = log.since(p.released, p.resumed if p.resumed is not None else end)
            p.moved_after_release = max_displacement(xy[held])
            p.still_after_release = all(not np.any(d) for d in log.duties[held]) and p.moved_after_release < STILL_M
    return found


def path_length(xy: np.ndarray) -> float:
    return float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) if len(xy) > 1 else 0.0


def max_displacement(xy: np.ndarray) -> float:
    """How far the base got from where the stretch began, m."""
    return float(np.max(np.hypot(*(xy - xy[0]).T))) if len(xy) else 0.0
