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
        (self.ids, self.x, self.p, self.born, self.seen, self.shape, self.radius,
         self._next_id) = _step(self.ids, self.x, self.p, self.born, self.seen, self.shape, self.radius, self._next_id,
                                stamp, dt, bodies.centre, bodies.confidence, bodies.radius, c.gate, c.accel_std,
                                c.measurement_std, c.drop_after)
        self.people = self._report(stamp)
        return self.people

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



@njit(cache=True)
def _step(ids, x, p, born, seen, shape, radius, next_id, stamp, dt, centre, confidence, body_radius,
          gate, accel_std, measurement_std, drop_after):
    """One scan's tracking on the arrays (``update``'s steps after detection): predict, match
    nearest first, correct the matched, start the rest, drop the long unseen. One compiled
    call: as numpy a dozen small calls (batched matmuls, concatenations) cost a third of the
    people tick for two or three tracks."""
    if ids.shape[0] and dt > 0:
        x, p = motion.predict(x, p, dt, accel_std)
    else:
        x, p = x.copy(), p.copy()
    shape, radius, seen = shape.copy(), radius.copy(), seen.copy()
    track, body = _nearest_first(x[:, :2].copy(), centre, gate)
    if track.shape[0]:
        xs, ps = motion.correct(x[track], p[track], centre[body], measurement_std ** 2)
        for k in range(track.shape[0]):
            t, b = track[k], body[k]
            x[t], p[t] = xs[k], ps[k]
            seen[t] = stamp
            shape[t] = max(shape[t], confidence[b])
            radius[t] = body_radius[b]
    fresh = np.ones(centre.shape[0], np.bool_)
    fresh[body] = False
    new = np.flatnonzero(fresh)
    bx, bp = motion.start(centre[new], measurement_std)
    keep = np.flatnonzero(stamp - seen < drop_after)
    n = keep.shape[0] + new.shape[0]
    out_ids, out_x, out_p = np.empty(n, ids.dtype), np.empty((n, 4)), np.empty((n, 4, 4))
    out_born, out_seen, out_shape, out_radius = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for k in range(keep.shape[0]):
        t = keep[k]
        out_ids[k], out_x[k], out_p[k] = ids[t], x[t], p[t]
        out_born[k], out_seen[k], out_shape[k], out_radius[k] = born[t], seen[t], shape[t], radius[t]
    for j in range(new.shape[0]):
        k, b = keep.shape[0] + j, new[j]
        out_ids[k], out_x[k], out_p[k] = next_id + j, bx[j], bp[j]
        out_born[k], out_seen[k], out_shape[k], out_radius[k] = stamp, stamp, confidence[b], body_radius[b]
    return out_ids, out_x, out_p, out_born, out_seen, out_shape, out_radius, next_id + new.shape[0]
