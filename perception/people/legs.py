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
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perception.people.config import PeopleConfig
from perception.people.segments import Segments, split, unwrap
from perception.people.shape import Fits, fit


def leg_sized(segments: Segments, config: PeopleConfig) -> np.ndarray:
    """(S,) bool: the segments that could be leg arcs by size alone (three returns or more, no
    wider than a leg): the only ones ``find`` fits a circle to."""
    return (segments.count >= 3) & (segments.width <= config.leg_width)


def arcs(segments: Segments, fits: Fits, robot_xy: np.ndarray, config: PeopleConfig) -> np.ndarray:
    """(S,) bool: which segments are leg arcs, seen from ``robot_xy``."""
    lo, hi = config.leg_radius
    seen = np.hypot(*(segments.centre - robot_xy).T)
    with np.errstate(invalid="ignore"):
        beyond = np.hypot(*(fits.circle_centre - robot_xy).T) > seen
    return (leg_sized(segments, config) & (fits.circle_rms <= config.arc_rms)
            & (fits.radius >= lo) & (fits.radius <= hi) & beyond)


def gaps(points: np.ndarray, segments: Segments, which: np.ndarray) -> np.ndarray:
    """(K, K) the least distance between an end of one of the segments ``which`` (indices) and
    an end of another, m: the ends facing each other across a gap, or meeting at a corner."""
    start = segments.start[which]
    ends = np.stack([points[start], points[start + segments.count[which] - 1]], axis=1)  # (K, 2, 2)
    d = np.hypot(*(ends[:, None, :, None, :] - ends[None, :, None, :, :]).transpose(4, 0, 1, 2, 3))
    return d.min(axis=(2, 3))


def pairs(points: np.ndarray, segments: Segments, fits: Fits, leg: np.ndarray, config: PeopleConfig) -> np.ndarray:
    """(S, S) bool, symmetric: the leg arcs ``leg`` that make a pair of legs (judged among the
    leg arcs alone: most scans have none or one)."""
    out = np.zeros((len(leg), len(leg)), bool)
    k = np.flatnonzero(leg)
    if len(k) < 2:
        return out
    c = fits.circle_centre[k]
    apart = np.hypot(*(c[:, None, :] - c[None, :, :]).transpose(2, 0, 1))
    lo, hi = config.leg_pair_distance
    out[np.ix_(k, k)] = (apart >= lo) & (apart <= hi) & (gaps(points, segments, k) >= config.leg_gap)
    return out


@dataclass(frozen=True)
class LegShapes:
    """One scan's shape evidence (map frame of the points given)."""

    pairs: np.ndarray
    """(K, 2) pairs of legs: the midpoints of their two circles' centres."""
    arcs: np.ndarray
    """(L, 2) every leg arc's circle centre (those of the pairs too)."""


def find(points: np.ndarray, robot_xy: np.ndarray, explained: np.ndarray, config: PeopleConfig) -> LegShapes:
    """The leg arcs and pairs of legs of one scan. ``points``: the revolution's returns in scan
    order; ``explained``: the map's and the known pots' (``explained.StaticScene``)."""
    order = unwrap(points)
    pts = np.asarray(points, dtype=float)[order]
    ranges = np.hypot(*(pts - robot_xy).T)
    keep = ~np.asarray(explained, dtype=bool)[order] & (ranges >= config.min_range) & (ranges <= config.max_range)
    index = np.flatnonzero(keep)
    pts, ranges = pts[keep], ranges[keep]
    segs = split(pts, ranges, config.jump, config.jump_per_metre, index)
    can = leg_sized(segs, config)  # the fits, most of the pass's cost, only where a leg could be
    pts, segs = pts[np.repeat(can, segs.count)], segs.subset(can)
    fits = fit(pts, segs)
    leg = arcs(segs, fits, robot_xy, config)
    i, j = np.nonzero(np.triu(pairs(pts, segs, fits, leg, config)))
    return LegShapes((fits.circle_centre[i] + fits.circle_centre[j]) / 2, fits.circle_centre[leg])
