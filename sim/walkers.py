"""People walking the simulated greenhouse (spec/world.md ``walkers``), moved kinematically.

Each walker goes along its path at its speed, waits ``pause`` seconds at each end and walks it
back (ping-pong), from ``start`` seconds on. It does not yield to the robot, except that it
stops while its next step would bring its body within ``KEEP_CLEAR`` of the robot's (people do
not walk into a machine) and goes on when that is clear. Its body is a circle of half its width
for that rule; the robot's is ``ROBOT_RADIUS``. The motion is advanced with the drive's
``pre_chunk`` beat (every 10 ms of sim time) from the sim's own state only: no randomness, so
the same world and seed give the same walk. ``hold`` stops and starts a walker (events).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from sim.engine import Engine
from sim.world_checks import ROBOT_RADIUS

KEEP_CLEAR = 0.3
"""A walker stops while its next step would bring it this close to the robot's body, m."""


@dataclass
class _Walk:
    path: np.ndarray
    """(N, 2) waypoints."""
    lengths: np.ndarray
    """Cumulative arc length at each waypoint."""
    speed: float
    pause: float
    start: float
    half: float
    mocap: int
    s: float = 0.0
    """How far along the path it is, m."""
    forward: bool = True
    resume_at: float = 0.0
    """Standing at an end of the path until then."""
    held: bool = False
    heading: float = field(default=0.0)

    def at(self, s: float) -> np.ndarray:
        return np.array([np.interp(s, self.lengths, self.path[:, 0]), np.interp(s, self.lengths, self.path[:, 1])])


class SimWalkers:
    def __init__(self, engine: Engine, walkers, robot_xy):
        """``robot_xy()``: the robot's true position (the rule needs where the machine is)."""
        self.engine, self.robot_xy = engine, robot_xy
        self.ids = [w.id for w in walkers]
        self._walks = {}
        for w in walkers:
            path = np.asarray(w.path, dtype=float)
            lengths = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
            body = engine.id(mujoco.mjtObj.mjOBJ_BODY, f"walker_{w.id}")
            walk = _Walk(path, lengths, w.speed, w.pause, w.start, w.width / 2, int(engine.model.body_mocapid[body]))
            walk.heading = math.atan2(path[1, 1] - path[0, 1], path[1, 0] - path[0, 0])
            self._walks[w.id] = walk
            self._place(walk)
        self._last: float | None = None

    def positions(self) -> dict[str, tuple[float, float, float]]:
        """Each walker's (x, y, body radius), world frame."""
        return {k: (float(p[0]), float(p[1]), w.half) for k, w in self._walks.items() for p in [w.at(w.s)]}

    def hold(self, walker: str, held: bool) -> None:
        """Stop a walker where it is (True) or let it walk on (False)."""
        if walker not in self._walks:
            raise ValueError(f"the world has no walker {walker!r}")
        self._walks[walker].held = held

    def pre_chunk(self, t: float) -> None:
        dt, self._last = (0.0 if self._last is None else t - self._last), t
        if dt <= 0:
            return
        rx, ry = self.robot_xy()
        for w in self._walks.values():
            if w.held or t < w.start or t < w.resume_at:
                continue
            step = w.speed * dt * (1 if w.forward else -1)
            s = min(max(w.s + step, 0.0), w.lengths[-1])
            (x, y), (x0, y0) = w.at(s), w.at(w.s)
            gap = math.hypot(x - rx, y - ry) - ROBOT_RADIUS - w.half
            if gap < KEEP_CLEAR and gap < math.hypot(x0 - rx, y0 - ry) - ROBOT_RADIUS - w.half:
                continue  # the next step would come too close to the machine: wait (a step away is fine)
            if s != w.s:
                w.heading = math.atan2(y - y0, x - x0)
            w.s = s
            if s in (0.0, w.lengths[-1]) and (s == w.lengths[-1]) == w.forward:
                w.forward = not w.forward
                w.resume_at = t + w.pause
            self._place(w)

    def _place(self, w: _Walk) -> None:
        d = self.engine.data
        x, y = w.at(w.s)
        d.mocap_pos[w.mocap] = (x, y, 0.0)
        d.mocap_quat[w.mocap] = (math.cos(w.heading / 2), 0.0, 0.0, math.sin(w.heading / 2))
