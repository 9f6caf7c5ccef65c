"""Configuration of the lidar person tracker (``perception.people``).

Numbers come from three places, each field says which: the sim's people (spec/world.md,
``sim.walkers``: legs of radius 0.07 m half the body's width apart, a cart up to 1.2 m wide and
0.6 m deep ahead of its pusher, a crouching worker one 0.5 x 0.6 m body), the RPLidar C1 (seed:
~500 returns per 10 Hz revolution, returns below 0.25 m are the robot's own arm) and
leg_tracker's rule of thumb (legs of one person within 0.8 m of each other).
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict


class PeopleConfig(Strict):
    """The person tracker on the lidar scan."""

    min_range: float = Field(0.0, ge=0)
    """Returns nearer the robot's centre than this are dropped, m (0: none). The robot's own
    returns are dropped by its outline as it stands, the chassis and the arm
    (``mission.runtime.people``), not by a circle: the seed's "consumers drop < 0.25 m" hid a
    worker's legs pressed to the chassis' front."""
    max_range: float = Field(6.0, gt=0)
    """Returns farther than this are not looked at, m: the distance rules act within ~1.5 m of
    the path, and at 6 m a leg is only ~2 returns of the C1's 500 (0.075 m apart)."""
    jump: float = Field(0.12, gt=0)
    """A gap wider than ``jump + jump_per_metre * range`` between neighbouring returns starts a
    new segment, m. 0.12 m parts two things a hand apart up close; the range term follows the
    C1's 0.0126 rad step (0.038 m at 3 m) so a leg at 6 m stays one segment."""
    jump_per_metre: float = Field(0.03, ge=0)
    """The range-proportional part of that gap, m per m of range."""
    min_segment_points: int = Field(2, ge=1)
    """A segment of fewer returns is dropped: a lone return is noise, or a wall seen at a
    grazing angle, whose returns lie farther apart than the jump. A leg gives 2 returns at
    5 m, 4 at 3 m."""
    min_body_points: int = Field(3, ge=1)
    """A body needs this many returns, all its segments together: one or two stray returns are
    the noisy fringe of a mapped wall or pot (the C1's ~1 cm noise), not a person. A leg at 3 m
    gives ~4 returns."""
    leg_width: float = Field(0.25, gt=0)
    """A segment no wider than this is leg-shaped, m: a leg is 0.14 m across (LEG_RADIUS 0.07)
    and the noise and the seen arc's ends add a few cm."""
    pair_distance: float = Field(0.8, gt=0)
    """Two leg-shaped segments whose centres lie this close are one person's legs, m
    (leg_tracker pairs legs within 0.8 m: a walking stride)."""
    join_gap: float = Field(0.3, ge=0)
    """Any two segments whose bounding boxes come this close are one body, m: a cart's rear is
    ~0.08 m from its pusher's legs (``sim.walkers``: cart centre 0.45 m ahead, half depth 0.3,
    legs of radius 0.07), while joining by centres within 0.8 m merged a worker standing by
    the wall with the parked cart beside them (``perception.people`` tuning world 1)."""
    max_extent: float = Field(1.7, gt=0)
    """A body wider than this (bounding-box diagonal) is not a person, m: a wall, a row of
    unmapped things. The widest person is a 1.2 m cart 0.6 m deep with its pusher's legs behind
    (diagonal ~1.5 m)."""
    depth: float = Field(0.07, ge=0)
    """The lidar sees the near side of a body: its centre is put this far behind what was seen,
    away from the robot, and its radius grows by as much, m (a leg's radius, 0.07)."""
    gate: float = Field(0.8, gt=0)
    """A detection farther than this from a track's predicted position does not update it, m:
    a person at 1.5 m/s moves 0.15 m per 10 Hz scan, and a body's seen centre jumps by up to
    half its width as the robot's view of it changes."""
    accel_std: float = Field(2.0, gt=0)
    """The constant-velocity filter's process noise, m/s^2: people start and stop within about
    half a second at walking speed (~1 m/s)."""
    measurement_std: float = Field(0.06, gt=0)
    """How far a detection's centre strays from the body's, m: the seen side changes with the
    view (a leg's radius) on top of the C1's ~1 cm range noise."""
    coast: float = Field(0.3, ge=0)
    """A track not seen for this long is still reported (at its predicted position, its
    confidence fading), s: a leg hidden behind the other for a few scans is not a person gone."""
    drop_after: float = Field(1.0, gt=0)
    """A track not seen for this long is deleted, s."""
    still_speed: float = Field(0.1, ge=0)
    """Speeds below this are reported as 0 (someone standing), m/s: the filter's jitter on a
    standing person is a few cm/s."""
    moving_speed: float = Field(0.3, ge=0)
    """A track that moves faster than this, once its velocity has settled, is a person for sure
    (confidence 1): pots, benches and walls do not walk, m/s."""
    settle_time: float = Field(1.0, ge=0)
    """How long a track must have been seen before its speed is trusted, s."""
    leg_radius: tuple[float, float] = (0.03, 0.085)
    """A leg arc's fitted radius lies in this window, m (``perception.people.legs``): legs are
    0.07 m (``sim.walkers.LEG_RADIUS``, real legs ~0.05-0.09) and fit 0.055-0.08 (10th to 75th
    percentile, synthetic C1 scans 0.8-2.5 m away) while the 0.10 m pots fit 0.088-0.11 (10th to
    90th): the window's top sits between; a short side-on sliver of a leg fits down to ~0.03."""
    arc_rms: float = Field(0.015, gt=0)
    """A leg arc's returns lie this close to their circle (RMS), m: the C1's ~1 cm noise plus a
    little; a box's corner (an L) fits a circle to 2-4 cm."""
    leg_pair_distance: tuple[float, float] = (0.1, 0.5)
    """Two leg arcs whose circles' centres lie this far apart are a pair of legs, m: standing
    legs are half the 0.45 m body apart (0.225), a stride opens them to ~0.5."""
    leg_gap: float = Field(0.03, ge=0)
    """The two arcs of a pair of legs have their nearest ends at least this far apart, m: a gap
    (standing legs are 0.085 m apart surface to surface), where a box's two faces meet at its
    corner with none."""
    legs_confidence: float = Field(0.9, ge=0, le=1)
    """Confidence of a body made of two or more leg-shaped segments (a pair of legs)."""
    leg_confidence: float = Field(0.6, ge=0, le=1)
    """Confidence of one leg-shaped segment alone (the other leg hidden, or a post)."""
    body_confidence: float = Field(0.5, ge=0, le=1)
    """Confidence of any other body near the robot that the map and the known pots do not
    explain (a cart, a crouching worker, an unmapped crate): a person until shown otherwise."""
    margin: float = Field(0.1, ge=0)
    """A return this close to a mapped occupied cell or a known pot's rim is explained by it, m:
    two 0.05 m cells, the C1's noise and the pots' placement (the map's pots fall ~1.3 cm from
    the world's)."""
