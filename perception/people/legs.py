"""Leg arcs and leg pairs: the shape evidence that a standing thing is a person (issue 28).

A box seen corner-on and a pair of legs can both be two narrow segments, and a moved pot's
unexplained sliver one: by size they are alike (``bodies``). leg_tracker tells them apart by
shape, and so do we, on the segment fits of ``shape``:

- a *leg arc* is a segment of at least three returns that a circle fits to within
  ``arc_rms`` (a box face or corner does not: straight, or an L), of radius within
  ``leg_radius`` (a leg is 0.07 m; the 0.10 m pots fit wider), bulging towards the lidar
  (its circle's centre lies beyond the returns: a leg is seen from outside);
- a *leg pair* is two leg arcs whose circles' centres lie ``leg_pair_distance`` apart (0.1-0.5
  m: two legs of one person, standing or in stride) with a gap between their returns of at
  least ``leg_gap``: two things, not two faces of one contiguous outline meeting at a corner.

One scan's single leg arc is not enough (a pot's sliver fits the leg window now and then, and a
post always); the runtime asks for one scan after scan (``mission.runtime.people``). A crouching
worker's outline is nothing but a blob to the lidar, the same as a crate's: those keep the
walked rule.

:func:`find` runs the whole shape pass on one scan. It segments the scan as the circle it is
(``segments.unwrap``: the revolution starts straight ahead, and whatever stood dead ahead was
cut in two at the array's ends, a box corner-on into two leg-wide faces) and breaks segments
where the map took returns out (``split``'s ``index``: the wall seen between a standing
person's legs, 0.085 m apart surface to surface, under the jump). The runtime runs it beside the tracker on every scan and gives its shapes to the nearest tracks.
The whole pass is one compiled call (numba), on the same kernels as ``segments`` and ``shape``:
its array version cost ~0.5 ms a scan in glue alone (issue 28 asks 1 ms for the whole tracker).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from perception.people.config import PeopleConfig
from perception.people.segments import Segments, _split, _unwrap
from perception.people.shape import DAMPING, GEOMETRIC_STEPS, Fits, _fit


@njit(cache=True)
def _leg_sized(count, lo, hi, leg_width):
    out = np.empty(len(count), np.bool_)
    for k in range(len(count)):
        out[k] = count[k] >= 3 and math.hypot(hi[k, 0] - lo[k, 0], hi[k, 1] - lo[k, 1]) <= leg_width
    return out


def leg_sized(segments: Segments, config: PeopleConfig) -> np.ndarray:
    """(S,) bool: the segments that could be leg arcs by size alone (three returns or more, no
    wider than a leg): the only ones ``find`` fits a circle to."""
    return _leg_sized(segments.count.astype(np.int64), segments.lo, segments.hi, config.leg_width)


@njit(cache=True)
def _arcs(centre, circle_centre, circle_rms, radius, robot_x, robot_y, arc_rms, lo, hi):
    """Which of the fitted (leg-sized) segments are leg arcs, seen from the robot."""
    out = np.zeros(len(radius), np.bool_)
    for k in range(len(radius)):
        seen = math.hypot(centre[k, 0] - robot_x, centre[k, 1] - robot_y)
        beyond = math.hypot(circle_centre[k, 0] - robot_x, circle_centre[k, 1] - robot_y) > seen  # nan: False
        out[k] = circle_rms[k] <= arc_rms and lo <= radius[k] <= hi and beyond
    return out


def arcs(segments: Segments, fits: Fits, robot_xy: np.ndarray, config: PeopleConfig) -> np.ndarray:
    """(S,) bool: which segments are leg arcs, seen from ``robot_xy``."""
    lo, hi = config.leg_radius
    return leg_sized(segments, config) & _arcs(segments.centre, fits.circle_centre, fits.circle_rms, fits.radius,
                                               float(robot_xy[0]), float(robot_xy[1]), config.arc_rms, lo, hi)


@njit(cache=True)
def _end_gap(points, start, count, a, b):
    """The least distance between an end of segment ``a`` and an end of segment ``b``, m: the
    ends facing each other across a gap, or meeting at a corner."""
    best = np.inf
    for i in (start[a], start[a] + count[a] - 1):
        for j in (start[b], start[b] + count[b] - 1):
            best = min(best, math.hypot(points[i, 0] - points[j, 0], points[i, 1] - points[j, 1]))
    return best


@njit(cache=True)
def _pairs(points, start, count, circle_centre, leg, near, far, min_gap):
    """(i, j), i < j, of the leg arcs ``leg`` whose circles' centres lie ``near``-``far`` apart
    and whose nearest ends are at least ``min_gap`` apart."""
    k = np.flatnonzero(leg)
    out = np.empty((len(k) * (len(k) - 1) // 2, 2), np.int64)
    n = 0
    for x in range(len(k)):
        for y in range(x + 1, len(k)):
            a, b = k[x], k[y]
            apart = math.hypot(circle_centre[a, 0] - circle_centre[b, 0], circle_centre[a, 1] - circle_centre[b, 1])
            if near <= apart <= far and _end_gap(points, start, count, a, b) >= min_gap:
                out[n, 0], out[n, 1] = a, b
                n += 1
    return out[:n]


def pairs(points: np.ndarray, segments: Segments, fits: Fits, leg: np.ndarray, config: PeopleConfig) -> np.ndarray:
    """(S, S) bool, symmetric: the leg arcs ``leg`` that make a pair of legs: their circles'
    centres ``leg_pair_distance`` apart, a gap of at least ``leg_gap`` between their returns."""
    found = _pairs(np.ascontiguousarray(points, dtype=np.float64), segments.start.astype(np.int64),
                   segments.count.astype(np.int64), fits.circle_centre, np.asarray(leg, dtype=np.bool_),
                   *config.leg_pair_distance, config.leg_gap)
    out = np.zeros((len(leg), len(leg)), bool)
    out[found[:, 0], found[:, 1]] = out[found[:, 1], found[:, 0]] = True
    return out


@dataclass(frozen=True)
class LegShapes:
    """One scan's shape evidence (map frame of the points given)."""

    pairs: np.ndarray
    """(K, 2) pairs of legs: the midpoints of their two circles' centres."""
    arcs: np.ndarray
    """(L, 2) every leg arc's circle centre (those of the pairs too)."""


@njit(cache=True)
def _find(points, explained, robot_x, robot_y, min_range, max_range, jump, jump_per_metre, leg_width,
          arc_rms, radius_lo, radius_hi, pair_near, pair_far, min_gap):
    order = _unwrap(points)
    n = len(order)
    pts, ranges, index = np.empty((n, 2)), np.empty(n), np.empty(n, np.int64)
    m = 0
    for k in range(n):
        i = order[k]
        r = math.hypot(points[i, 0] - robot_x, points[i, 1] - robot_y)
        if not explained[i] and min_range <= r <= max_range:
            pts[m, 0], pts[m, 1], ranges[m], index[m] = points[i, 0], points[i, 1], r, k
            m += 1
    if m == 0:
        return np.zeros((0, 2)), np.zeros((0, 2))
    start, count, centre, lo, hi = _split(pts[:m], ranges[:m], jump, jump_per_metre, index[:m])
    can = np.flatnonzero(_leg_sized(count, lo, hi, leg_width))
    start, count, centre = start[can], count[can], centre[can]  # the fits, only where a leg could be
    _, radius, circle_rms, circle_centre = _fit(pts, start, count, GEOMETRIC_STEPS, DAMPING)
    leg = _arcs(centre, circle_centre, circle_rms, radius, robot_x, robot_y, arc_rms, radius_lo, radius_hi)
    found = _pairs(pts, start, count, circle_centre, leg, pair_near, pair_far, min_gap)
    mids = np.empty((len(found), 2))
    for k in range(len(found)):
        for c in range(2):
            mids[k, c] = (circle_centre[found[k, 0], c] + circle_centre[found[k, 1], c]) / 2
    return mids, circle_centre[leg]


def find(points: np.ndarray, robot_xy: np.ndarray, explained: np.ndarray, config: PeopleConfig) -> LegShapes:
    """The leg arcs and pairs of legs of one scan. ``points``: the revolution's returns in scan
    order; ``explained``: the map's and the known pots' (``explained.StaticScene``)."""
    c = config
    if not len(points):
        return LegShapes(np.zeros((0, 2)), np.zeros((0, 2)))
    return LegShapes(*_find(np.ascontiguousarray(points, dtype=np.float64), np.asarray(explained, dtype=np.bool_),
                            float(robot_xy[0]), float(robot_xy[1]), c.min_range, c.max_range, c.jump,
                            c.jump_per_metre, c.leg_width, c.arc_rms, *c.leg_radius, *c.leg_pair_distance, c.leg_gap))
