"""From segments to bodies: legs paired, a cart joined to its pusher, each body's shape scored.

leg_tracker classifies each segment and pairs legs within 0.8 m; we do the same with the one
feature that separates the greenhouse's people from what is left once the map and the known
pots have explained their returns: size. Two leg-wide segments whose centres lie within
``pair_distance`` are a pair of legs, and any two segments that nearly touch (``join_gap``) are
one thing; connected components of those links are the bodies (so a cart and the two legs
behind it are one body, as ``hw.people.Person`` asks, while a worker standing beside a parked
cart stays a person of their own); a body wider than ``max_extent`` is a wall or a row of things, not
a person; a body of two or more leg-wide segments is a pair of legs (most confident), one
leg-wide segment a leg alone, anything else a compact unexplained body (a cart seen from the
front, a crouching worker's outline, an unmapped crate), a person until shown otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from perception.people.config import PeopleConfig
from perception.people.segments import Segments, _split


@dataclass(frozen=True)
class Bodies:
    """Person candidates of one scan, as arrays over the bodies."""

    centre: np.ndarray
    """(B, 2) the body's estimated centre on the floor (odom frame)."""
    radius: np.ndarray
    """(B,) radius of a circle holding what was seen, plus the unseen far side, m."""
    confidence: np.ndarray
    """(B,) how person-like the shape is (config: legs, leg, body confidence)."""

    def __len__(self) -> int:
        return len(self.centre)


@njit(cache=True)
def _root(root, a):
    while root[a] != a:
        root[a] = root[root[a]]
        a = root[a]
    return a


@njit(cache=True)
def _group(points, start, count, lo, hi, centre, robot_x, robot_y, min_segment_points, min_body_points,
           leg_width, pair_distance, join_gap, max_extent, depth, confidences):
    """``group`` in one compiled pass: links, components, each body's box, centre, reach, score."""
    kept = np.flatnonzero(count >= min_segment_points)
    k = len(kept)
    legs = np.empty(k, np.bool_)
    for a in range(k):
        s = kept[a]
        legs[a] = math.hypot(hi[s, 0] - lo[s, 0], hi[s, 1] - lo[s, 1]) <= leg_width
    root = np.arange(k)
    for a in range(k):
        sa = kept[a]
        for b in range(a + 1, k):
            sb = kept[b]
            linked = legs[a] and legs[b] and math.hypot(centre[sa, 0] - centre[sb, 0],
                                                        centre[sa, 1] - centre[sb, 1]) <= pair_distance
            if not linked:
                gx = max(lo[sb, 0] - hi[sa, 0], lo[sa, 0] - hi[sb, 0], 0.0)
                gy = max(lo[sb, 1] - hi[sa, 1], lo[sa, 1] - hi[sb, 1], 0.0)
                linked = math.hypot(gx, gy) <= join_gap
            if linked:
                ra, rb = _root(root, a), _root(root, b)
                if ra != rb:
                    root[max(ra, rb)] = min(ra, rb)
    # each component is labelled by its first segment: numbered in that order
    label = np.empty(k, np.int64)
    bodies = 0
    for a in range(k):
        r = _root(root, a)
        if r == a:
            label[a] = bodies
            bodies += 1
        else:
            label[a] = label[r]
    blo, bhi = np.full((bodies, 2), np.inf), np.full((bodies, 2), -np.inf)
    points_in, leg_parts, parts = np.zeros(bodies, np.int64), np.zeros(bodies, np.int64), np.zeros(bodies, np.int64)
    for a in range(k):
        s, b = kept[a], label[a]
        for c in range(2):
            blo[b, c] = min(blo[b, c], lo[s, c])
            bhi[b, c] = max(bhi[b, c], hi[s, c])
        points_in[b] += count[s]
        leg_parts[b] += legs[a]
        parts[b] += 1
    middle = np.empty((bodies, 2))
    for b in range(bodies):
        sx, sy = (blo[b, 0] + bhi[b, 0]) / 2, (blo[b, 1] + bhi[b, 1]) / 2
        ax, ay = sx - robot_x, sy - robot_y
        norm = max(math.hypot(ax, ay), 1e-9)
        middle[b, 0], middle[b, 1] = sx + depth * ax / norm, sy + depth * ay / norm
    # each return's distance to its body's centre: the body's radius is the farthest one's
    reach = np.zeros(bodies)
    for a in range(k):
        s, b = kept[a], label[a]
        for i in range(start[s], start[s] + count[s]):
            reach[b] = max(reach[b], math.hypot(points[i, 0] - middle[b, 0], points[i, 1] - middle[b, 1]))
    keep = np.empty(bodies, np.bool_)
    score = np.empty(bodies)
    for b in range(bodies):
        keep[b] = points_in[b] >= min_body_points and math.hypot(bhi[b, 0] - blo[b, 0], bhi[b, 1] - blo[b, 1]) <= max_extent
        score[b] = (confidences[0] if leg_parts[b] >= 2 and leg_parts[b] == parts[b]
                    else confidences[1] if leg_parts[b] == 1 and parts[b] == 1 else confidences[2])
    return middle[keep], reach[keep] + depth, score[keep]


def _scalars(c: PeopleConfig) -> tuple:
    return (c.min_segment_points, c.min_body_points, c.leg_width, c.pair_distance, c.join_gap, c.max_extent, c.depth,
            np.array([c.legs_confidence, c.leg_confidence, c.body_confidence]))


def group(points: np.ndarray, segments: Segments, robot_xy: np.ndarray, config: PeopleConfig) -> Bodies:
    """The scan's bodies: ``points`` the returns the segments index (scan order). Leg-wide
    segments whose centres lie within ``pair_distance`` (a pair of legs), or any two whose
    bounding boxes come within ``join_gap`` (a cart and its pusher), are linked; the connected
    components of the links are the bodies (union-find, the smaller root kept), numbered by
    their first segment, each scored by its parts (module docstring). One compiled pass
    (numba): a scan has a few dozen segments, and the array version's calls cost more than
    the arithmetic."""
    if not len(segments.count):
        return Bodies(np.zeros((0, 2)), np.zeros(0), np.zeros(0))
    return Bodies(*_group(np.ascontiguousarray(points, dtype=np.float64), segments.start.astype(np.int64),
                          segments.count.astype(np.int64), segments.lo, segments.hi, segments.centre,
                          float(robot_xy[0]), float(robot_xy[1]), *_scalars(config)))


@njit(cache=True)
def _detect(points, explained, robot_x, robot_y, min_range, max_range, jump, jump_per_metre, min_segment_points,
            min_body_points, leg_width, pair_distance, join_gap, max_extent, depth, confidences):
    n = points.shape[0]
    pts, ranges = np.empty((n, 2)), np.empty(n)
    m = 0
    for i in range(n):
        r = math.hypot(points[i, 0] - robot_x, points[i, 1] - robot_y)
        if not explained[i] and min_range <= r <= max_range:
            pts[m, 0], pts[m, 1], ranges[m] = points[i, 0], points[i, 1], r
            m += 1
    if m == 0:
        return np.zeros((0, 2)), np.zeros(0), np.zeros(0)
    pts = pts[:m]
    start, count, centre, lo, hi = _split(pts, ranges[:m], jump, jump_per_metre, np.zeros(0, np.int64))
    return _group(pts, start, count, lo, hi, centre, robot_x, robot_y, min_segment_points, min_body_points,
                  leg_width, pair_distance, join_gap, max_extent, depth, confidences)


def detect(points: np.ndarray, robot_xy: tuple[float, float], explained: np.ndarray, config: PeopleConfig) -> Bodies:
    """One scan's bodies from its returns (N, 2, scan order): those ``explained`` (the map's and
    the known pots', N bool) and those outside ``min_range``-``max_range`` left out, the rest
    split into segments (``segments``) and grouped. One compiled call."""
    c = config
    if not len(points):
        return Bodies(np.zeros((0, 2)), np.zeros(0), np.zeros(0))
    return Bodies(*_detect(np.ascontiguousarray(points, dtype=np.float64), np.asarray(explained, dtype=np.bool_),
                           float(robot_xy[0]), float(robot_xy[1]), c.min_range, c.max_range, c.jump, c.jump_per_metre,
                           *_scalars(c)))
