"""What a scenario judge records of a simulated run, once per control tick, from outside the stack.

It listens to the sim drivetrain's duty writes (one per tick of the base controller, so one row
per control tick) and at each samples what the judge needs and the robot never reads back:

* the duties that reached the motors (and the sim motors' dead zone) and the sim's true base
  pose (ground truth);
* the twist the base controller was handed that tick and the mux source that owned it;
* SLAM's map as it stands (how many cells it knows) and how many workers it has spawned.

Ground truth is read here only to judge, never fed back.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hw.base_controller import BaseController
from sim.backend import SimRobot


@dataclass
class MotionLog:
    sim: SimRobot | None
    base: BaseController | None = None
    slam: Any = None
    """Navigation's localisation; its ``occupancy`` and ``spawned`` are sampled when it has them
    (SLAM), else the map columns stay zero."""
    t: list[float] = field(default_factory=list)
    duties: list[np.ndarray] = field(default_factory=list)
    pose: list[tuple[float, float, float]] = field(default_factory=list)
    """True base pose (x, y, yaw), world frame."""
    command: list[tuple[float, float, float]] = field(default_factory=list)
    """The body twist the base controller used that tick (zero while stopped)."""
    source: list[str] = field(default_factory=list)
    """Who owned the wheels: a mux source, ``idle``, or why the base was held stopped."""
    known: list[int] = field(default_factory=list)
    """Cells SLAM's map knows (free or occupied); 0 while there is no map."""
    workers: list[int] = field(default_factory=list)
    """SLAM workers spawned so far."""
    dead_zone: float = 0.0
    """|duty| below which the motors do not turn (the sim motor's own, ``sim.drive.dead_zone``)."""
    _map: Any = None
    _known: int = 0

    def attach(self) -> "MotionLog":
        self.dead_zone = self.sim.drive.drive.dead_zone
        self.sim.drive.listeners.append(self._write)
        return self

    def _write(self, t: float, duties: np.ndarray) -> None:
        pose = self.sim.truth()
        c = self.base.command if self.base is not None else None
        self.add(t, duties, (pose.x, pose.y, pose.yaw), (c.vx, c.vy, c.wz) if c else (0.0, 0.0, 0.0),
                 self.base.source if self.base is not None else "", *self._slam())

    def _slam(self) -> tuple[int, int]:
        occupancy = getattr(self.slam, "occupancy", None)
        if occupancy is not self._map:  # count a map once, when a new one arrives
            self._map = occupancy
            self._known = 0 if occupancy is None else int(np.count_nonzero(occupancy.occupancy >= 0))
        return self._known, int(getattr(self.slam, "spawned", 0))

    def add(self, t: float, duties, pose: tuple[float, float, float], command=(0.0, 0.0, 0.0), source: str = "",
            known: int = 0, workers: int = 0) -> None:
        """One control tick's row (also how tests write a run by hand)."""
        self.t.append(t)
        self.duties.append(np.asarray(duties, dtype=float))
        self.pose.append(pose)
        self.command.append(tuple(command))
        self.source.append(source)
        self.known.append(known)
        self.workers.append(workers)

    def driven(self, s: slice) -> np.ndarray:
        """Per tick of ``s``: did any duty reach past the motors' dead zone (could it turn a wheel)?"""
        duties = np.abs(np.asarray(self.duties[s], dtype=float).reshape(-1, 4))
        return np.any(duties >= self.dead_zone if self.dead_zone > 0 else duties > 0, axis=1)

    @property
    def xy(self) -> np.ndarray:
        return np.asarray(self.pose, dtype=float).reshape(-1, 3)[:, :2]

    def after(self, start: float, end: float) -> slice:
        """Samples strictly after ``start`` up to ``end``."""
        t = np.asarray(self.t)
        return slice(int(np.searchsorted(t, start, side="right")), int(np.searchsorted(t, end, side="right")))

    def since(self, start: float, end: float) -> slice:
        """From the last sample at or before ``start`` (where the robot was then) up to ``end``."""
        s = self.after(start, end)
        return slice(max(s.start - 1, 0), s.stop)

    def speed_at(self, t: float) -> float:
        """True base speed over the control tick up to ``t``, m/s (0 before two ticks)."""
        i = self.since(t, t).start
        if i < 1:
            return 0.0
        xy = self.xy
        return float(np.hypot(*(xy[i] - xy[i - 1])) / max(self.t[i] - self.t[i - 1], 1e-9))
