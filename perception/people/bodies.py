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

from dataclasses import dataclass

import numpy as np

from perception.people.config import PeopleConfig
from perception.people.segments import Segments


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


def links(segments: Segments, config: PeopleConfig) -> np.ndarray:
    """(S, S) bool: two leg-shaped segments whose centres lie within ``pair_distance`` (a pair
    of legs), or any two whose bounding boxes come within ``join_gap`` (a cart and its pusher)."""
    c = segments.centre
    legs = segments.width <= config.leg_width
    paired = (np.hypot(*(c[:, None, :] - c[None, :, :]).transpose(2, 0, 1)) <= config.pair_distance) \
        & legs[:, None] & legs[None, :]
    apart = np.maximum(np.maximum(segments.lo[None, :, :] - segments.hi[:, None, :],
                                  segments.lo[:, None, :] - segments.hi[None, :, :]), 0.0)
    return paired | (np.hypot(*apart.transpose(2, 0, 1)) <= config.join_gap)


def components(near: np.ndarray) -> np.ndarray:
    """Labels of the connected components of the (symmetric) link matrix ``near``: each node
    labelled by the smallest index in its component. Union-find over the links, the smaller
    root kept: a scan has a few dozen segments and fewer links, which a loop walks faster than
    repeated passes over the whole matrix."""
    root = list(range(len(near)))

    def find(a: int) -> int:
        while root[a] != a:
            root[a] = a = root[root[a]]
        return a

    for a, b in zip(*(k.tolist() for k in np.nonzero(near))):
        ra, rb = find(a), find(b)
        if ra != rb:
            root[max(ra, rb)] = min(ra, rb)
    return np.array([find(a) for a in range(len(root))], dtype=int)


def group(points: np.ndarray, segments: Segments, robot_xy: np.ndarray, config: PeopleConfig) -> Bodies:
    """The scan's bodies: ``points`` the returns the segments index (scan order)."""
    enough = segments.count >= config.min_segment_points
    if not enough.all():
        kept = np.repeat(enough, segments.count)
        points, segments = points[kept], segments.subset(enough)
    if not len(segments.count):
        return Bodies(np.zeros((0, 2)), np.zeros(0), np.zeros(0))
    labels = components(links(segments, config))
    # each component is labelled by its first segment's index: numbered in that order
    first = labels == np.arange(len(labels))
    label = (np.cumsum(first) - 1)[labels]
    b = int(first.sum())
    lo = np.full((b, 2), np.inf)
    hi = np.full((b, 2), -np.inf)
    np.minimum.at(lo, label, segments.lo)
    np.maximum.at(hi, label, segments.hi)
    count = np.bincount(label, segments.count, minlength=b)
    legs = np.bincount(label, segments.width <= config.leg_width, minlength=b)
    parts = np.bincount(label, minlength=b)
    keep = (count >= config.min_body_points) & (np.hypot(*(hi - lo).T) <= config.max_extent)
    seen = (lo + hi) / 2
    away = seen - robot_xy
    away /= np.maximum(np.hypot(*away.T), 1e-9)[:, None]
    centre = seen + config.depth * away
    # each return's distance to its body's centre: the body's radius is the farthest one's
    point_label = np.repeat(label, segments.count)
    reach = np.zeros(b)
    np.maximum.at(reach, point_label, np.hypot(*(points - centre[point_label]).T))
    confidence = np.where((legs >= 2) & (legs == parts), config.legs_confidence,
                          np.where((legs == 1) & (parts == 1), config.leg_confidence, config.body_confidence))
    return Bodies(centre[keep], (reach + config.depth)[keep], confidence[keep])
