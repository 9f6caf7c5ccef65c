"""The person tracker: the scan's unexplained returns in, tracked people out, at the scan rate.

Per scan: drop the returns the static map or a known pot explains (``explained``), the robot's
own arm and what lies beyond ``max_range``; split the rest into segments (``segments``), join
them into bodies and score their shape (``bodies``); predict every track with its
constant-velocity filter (``motion``), give each track the nearest body within ``gate``
(greedy on distance, nearest pair first: with a handful of people in a greenhouse aisle that is
what the Hungarian method would choose), correct the matched tracks, start a track per body
left over, and delete tracks unseen for ``drop_after``. A track is reported from its first
detection (anything unexplained near the path is a person until shown otherwise) while it was
seen within ``coast``; its confidence is the most person-like shape it has shown, 1 once it has
walked, fading while it is not seen.

Nothing here reads a clock: time is the scan's ``stamp``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from hw.people import Person
from perception.people import motion
from perception.people.bodies import Bodies, detect
from perception.people.config import PeopleConfig


class PersonTracker:
    """Tracks people on the lidar scan, at the scan rate."""

    def __init__(self, config: PeopleConfig):
        self.config = config
        self._next_id = 1
        self._stamp: float | None = None
        self.ids = np.zeros(0, dtype=int)
        self.x = np.zeros((0, 4))
        self.p = np.zeros((0, 4, 4))
        self.born = np.zeros(0)
        self.seen = np.zeros(0)
        self.shape = np.zeros(0)
        self.radius = np.zeros(0)
        self.people: tuple[Person, ...] = ()
        """The people of the last update (what a ``hw.people.PeopleSource`` hands out)."""

    def __call__(self) -> tuple[Person, ...]:
        """The tracker as a ``hw.people.PeopleSource``: the last update's people."""
        return self.people

    def detect(self, points: np.ndarray, robot: tuple[float, float, float], explained: np.ndarray) -> Bodies:
        """One scan's person candidates (no tracking): see :meth:`update`."""
        return detect(np.asarray(points, dtype=float).reshape(-1, 2), robot[:2], explained, self.config)

    def update(self, stamp: float, points: np.ndarray, robot: tuple[float, float, float],
               explained: np.ndarray) -> tuple[Person, ...]:
        """One scan: ``stamp`` its time (s, the runtime's clock), ``points`` its valid returns
        as (N, 2) in the odom frame and in scan order (neighbours in angle are neighbours in the
        array), ``robot`` the robot's odom pose (x, y, yaw), ``explained`` an (N,) bool mask of
        the returns the static map or a known pot accounts for (``explained.StaticScene``).
        Returns the current people (odom frame), each with its confidence."""
        c = self.config
        bodies = self.detect(points, robot, explained)
        dt = 0.0 if self._stamp is None else max(stamp - self._stamp, 0.0)
        self._stamp = stamp
        if len(self.ids) and dt > 0:
            self.x, self.p = motion.predict(self.x, self.p, dt, c.accel_std)
        track, body = self._associate(bodies)
        if len(track):
            self.x[track], self.p[track] = motion.correct(self.x[track], self.p[track], bodies.centre[body],
                                                          c.measurement_std)
            self.seen[track] = stamp
            self.shape[track] = np.maximum(self.shape[track], bodies.confidence[body])
            self.radius[track] = bodies.radius[body]
        left = np.ones(len(bodies), bool)
        left[body] = False
        fresh = np.flatnonzero(left)
        if len(fresh):
            x, p = motion.start(bodies.centre[fresh], c.measurement_std)
            self.ids = np.concatenate([self.ids, self._next_id + np.arange(len(fresh))])
            self._next_id += len(fresh)
            self.x, self.p = np.concatenate([self.x, x]), np.concatenate([self.p, p])
            self.born = np.concatenate([self.born, np.full(len(fresh), stamp)])
            self.seen = np.concatenate([self.seen, np.full(len(fresh), stamp)])
            self.shape = np.concatenate([self.shape, bodies.confidence[fresh]])
            self.radius = np.concatenate([self.radius, bodies.radius[fresh]])
        alive = stamp - self.seen < c.drop_after
        if not alive.all():
            for name in ("ids", "x", "p", "born", "seen", "shape", "radius"):
                setattr(self, name, getattr(self, name)[alive])
        self.people = self._report(stamp)
        return self.people

    def _associate(self, bodies: Bodies) -> tuple[np.ndarray, np.ndarray]:
        """Matched (track indices, body indices): nearest pairs first, each within the gate."""
        if not len(self.ids) or not len(bodies):
            return np.zeros(0, int), np.zeros(0, int)
        return _nearest_first(np.ascontiguousarray(self.x[:, :2]), bodies.centre, self.config.gate)

    def _report(self, stamp: float) -> tuple[Person, ...]:
        c = self.config
        missed = stamp - self.seen
        speed = np.hypot(self.x[:, 2], self.x[:, 3])
        walked = (speed > c.moving_speed) & (self.seen - self.born >= c.settle_time)
        confidence = np.where(walked, 1.0, self.shape) * (1.0 - missed / c.drop_after)
        still = speed < c.still_speed
        shown = missed <= c.coast
        return tuple(Person(k, x, y, 0.0 if s else vx, 0.0 if s else vy, r, round(p, 3))
                     for k, (x, y, vx, vy), r, p, s in zip(self.ids[shown].tolist(), self.x[shown].tolist(),
                                                          self.radius[shown].tolist(), confidence[shown].tolist(),
                                                          still[shown].tolist()))


@njit(cache=True)
def _nearest_first(tracks, bodies, gate):
    """Greedy matching on distance, the nearest (track, body) pair first, each within ``gate``."""
    d = np.empty(tracks.shape[0] * bodies.shape[0])
    for t in range(tracks.shape[0]):
        for b in range(bodies.shape[0]):
            d[t * bodies.shape[0] + b] = math.hypot(tracks[t, 0] - bodies[b, 0], tracks[t, 1] - bodies[b, 1])
    used_t, used_b = np.zeros(tracks.shape[0], np.bool_), np.zeros(bodies.shape[0], np.bool_)
    most = min(tracks.shape[0], bodies.shape[0])
    matched_t, matched_b = np.empty(most, np.int64), np.empty(most, np.int64)
    n = 0
    for flat in np.argsort(d, kind="mergesort"):
        if d[flat] > gate:
            break
        t, b = flat // bodies.shape[0], flat % bodies.shape[0]
        if used_t[t] or used_b[b]:
            continue
        used_t[t] = used_b[b] = True
        matched_t[n], matched_b[n] = t, b
        n += 1
    return matched_t[:n], matched_b[:n]


def odom_points(scan_angles: np.ndarray, scan_ranges: np.ndarray, lidar_pose: tuple[float, float, float]) -> np.ndarray:
    """A scan's finite returns as (N, 2) points in scan order, given the lidar's pose in the
    frame wanted (odom, or map for :class:`~perception.people.explained.StaticScene`)."""
    return _odom_points(np.ascontiguousarray(scan_angles, dtype=np.float64),
                        np.ascontiguousarray(scan_ranges, dtype=np.float64), *map(float, lidar_pose))


@njit(cache=True)
def _odom_points(angles, ranges, x, y, yaw):
    out = np.empty((ranges.shape[0], 2))
    n = 0
    for i in range(ranges.shape[0]):
        if math.isfinite(ranges[i]):
            a = angles[i] + yaw
            out[n, 0], out[n, 1] = x + ranges[i] * math.cos(a), y + ranges[i] * math.sin(a)
            n += 1
    return out[:n]
