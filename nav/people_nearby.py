"""Where people keep the robot out, and the step out of a person's way (issue 28 item 2).

The navigator asks this for the people the costmaps' person layer counts (confidence at least
the layer's ``min_confidence``): each person's keep-out (their radius, the ``clearance`` and the
robot's radius) reaching along their next ``predict_time`` seconds of walking, in the map frame,
to tell a goal a person stands on and a robot a walker is coming at. When the robot stands in a
keep-out it does not just stand there: ``evade`` steps it out (at ``NEAR_SPEED``, the issue's most
within 1.0 m of a person, or the layer's ``step_speed`` farther off) towards the nearest place
out of *everyone's* way (``nav.refuge``): a step away from one person must not lead into the
walk of another.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from hw.odometry import Pose2D
from hw.people import Person, PeopleSource
from nav.config import NavConfig
from nav.costmap.grid import LETHAL, CostGrid
from nav.frames import transform_points
from nav.refuge import TOUCH, refuge_heading  # TOUCH: also ``in_lane``'s margin within ``wait_clearance``
from nav.walks import WALKING, walks_of

#: Speed of a step out of a person's way within ``wait_clearance`` (1 m) of them, m/s: issue
#: 28's most within 1.0 m of a person (farther off, the layer's faster ``step_speed``).
NEAR_SPEED = 0.15


class PeopleNearby:
    def __init__(self, config: NavConfig, people: PeopleSource, map_to_odom: Callable[[], Pose2D]):
        self.layer = config.costmap.global_costmap.people
        self.robot_radius = config.costmap.robot_radius
        self.people, self.map_to_odom = walks_of(people), map_to_odom
        self._refuge: np.ndarray | None = None
        """Where the last step out of someone's way headed (odom), kept while it stays a refuge
        (``nav.refuge.STICK``); forgotten once no step is wanted."""

    def counted(self) -> list[Person]:
        """The tracker's people the person layer counts (each read remembers their walks)."""
        return [p for p in self.people() if p.confidence >= self.layer.min_confidence]

    def walks(self, people: list[Person]) -> np.ndarray:
        """(P, 5) rows of x, y, vx, vy, radius, odom frame, of ``people`` as ``counted`` last read
        them (it stored each strider's velocity as it is), with someone slower given the velocity
        of their last walk (``nav.refuge`` keeps out of their lane): a cart pusher pausing at the
        end of a cross aisle turns and walks it again (safety.people seed 4: the robot took the
        paused cart's aisle for a place to wait in, and was in its way when it came back)."""
        return np.array([[p.x, p.y, *self.people.last(p), p.radius] for p in people], dtype=float)

    def gap(self, person: Person, x: float, y: float) -> float:
        """Body to body from a robot centred at (``x``, ``y``), odom, to ``person``, m."""
        return person.gap(x, y, self.robot_radius)

    def keep_out(self, person: Person, clearance: float | None = None) -> float:
        """Centre to centre, m: ``clearance`` (the layer's when None) body to body."""
        return person.radius + (self.layer.clearance if clearance is None else clearance) + self.robot_radius

    def in_map(self, people: list[Person] | None = None) -> list[tuple[np.ndarray, np.ndarray, float]]:
        """(where, where in ``predict_time``, keep_out) of every person counted (or of
        ``people``), map frame."""
        people = self.counted() if people is None else people
        if not people:
            return []
        now, then = self._segments(people)
        m2o = self.map_to_odom()
        now, then = transform_points(m2o, now), transform_points(m2o, then)
        return [(a, b, self.keep_out(p)) for a, b, p in zip(now, then, people)]

    def turns_in_map(self) -> list[tuple[float, float, float]]:
        """(x, y, reach) of where people turned round lately (``nav.walks.Walks.turns``), map frame."""
        turns = self.people.turns()
        if not turns:
            return []
        xy = transform_points(self.map_to_odom(), np.array([t[:2] for t in turns], dtype=float))
        return [(float(x), float(y), t[2]) for (x, y), t in zip(xy, turns)]

    def in_keep_out(self, x: float, y: float, ahead: bool = True, people: list[Person] | None = None) -> bool:
        """Is the map point within a person's keep-out (of everyone counted, or of ``people``),
        their next steps included (``ahead``) or where they are now only?"""
        return any(to_segment(np.array([x, y]), a, b if ahead else a) < r for a, b, r in self.in_map(people))

    def in_a_walkers_keep_out(self, x: float, y: float) -> bool:
        """Is the map point within the keep-out of someone seen to walk (``Walks.walked``)? A
        grower who stopped for the robot walks on once it is out of their way; a worker who
        stands, or a crate on a pot's approach pose taken for a person, does not, and is waited
        for (``mission.patrol.aside`` looks from beside a taken pose)."""
        return self.in_keep_out(x, y, people=[p for p in self.counted() if self.people.walked(p)])

    def inside(self, xy: np.ndarray) -> np.ndarray:
        """Which of the (N, 2) map points lie within anyone's keep-out, their next steps
        included: ``in_keep_out`` for a whole path at once (the people read once)."""
        out = np.zeros(len(xy), dtype=bool)
        for a, b, r in self.in_map():
            out |= to_segments(xy[:, 0], xy[:, 1], a, b) < r
        return out

    def way_out(self, free: CostGrid, x: float, y: float) -> CostGrid:
        """``free`` (the planner's grid with the people's bodies taken out) with everyone's
        keep-out laid back in, each shrunk to just inside the robot at map (``x``, ``y``): from
        inside someone's keep-out, a plan whose every step keeps at least as far from everyone
        as the robot stands now. A grower who stopped for the robot at arm's length waits for it
        to leave their way; planning from inside their keep-out had no start, and the robot
        stood there with them (safety.people seed 107, 470 s: a cart pusher and the robot
        waited for each other for 400 s at the end of the north aisle)."""
        data, geo = free.data.copy(), free.geometry
        cx, cy = geo.centre_of(np.arange(geo.width)[None, :], np.arange(geo.height)[:, None])
        here = np.array([x, y])
        for a, b, keep_out in self.in_map():
            reach = min(keep_out, to_segment(here, a, b) - free.resolution)
            data[to_segments(cx, cy, a, b) < reach] = LETHAL
        return CostGrid(data, free.resolution, free.origin_x, free.origin_y)

    def in_lane(self, odom: Pose2D) -> bool:
        """Is the robot (at ``odom``) in the lane of someone walking its way (module docstring)?"""
        here = np.array([odom.x, odom.y])
        walking = [p for p in self.counted()
                   if math.hypot(p.vx, p.vy) > WALKING and (here - [p.x, p.y]) @ [p.vx, p.vy] > 0.0]
        if not walking:
            return False
        now, then = self._segments(walking, self.layer.lane_time)
        return any(to_segment(here, a, b) < self._lane_width(p, here) for p, a, b in zip(walking, now, then))

    def _lane_width(self, person: Person, here: np.ndarray) -> float:
        """How near their walk puts the robot in their lane, centre to centre: the keep-out while
        they are beyond ``wait_clearance``; nearer, only a walk that would touch the robot
        (``TOUCH`` between bodies). Someone already at arm's length who will pass it by is let
        pass by a robot standing still; stepping away then is moving beside them."""
        if self.gap(person, *here) > self.layer.wait_clearance:
            return self.keep_out(person)
        return person.radius + self.robot_radius + TOUCH

    def evade(self, odom: Pose2D, grid: CostGrid, clearance: float | None = None,
              reach: float | None = None) -> Twist:
        """A step out of the way of the nearest person whose keep-out the robot (at ``odom``) is
        in, free on ``grid`` (the local costmap without people); zero with nobody that close or
        no free direction. ``clearance``: the body-to-body distance to keep (the layer's when
        None; the wider ``wait_clearance`` while the robot waits for someone); ``reach``: how
        many seconds of a walker's walk the keep-out runs along (``predict_time`` when None, the
        ``lane_time`` to step out of a lane)."""
        people = self.counted()
        here = np.array([odom.x, odom.y])
        close = [(p, d) for p, a, b in zip(people, *self._segments(people, reach))
                 if (d := to_segment(here, a, b)) < self.keep_out(p, clearance)] if people else []
        if not close:
            self._refuge = None
            return ZERO_TWIST
        p = min(close, key=lambda c: c[1])[0]
        v = self.layer.step_speed if self.gap(p, odom.x, odom.y) > self.layer.wait_clearance else NEAR_SPEED
        rows = self.walks(people)
        want = self.layer.clearance if clearance is None else clearance
        turns = np.array(self.people.turns(), dtype=float).reshape(-1, 3)
        step = refuge_heading(here, rows, grid, self.robot_radius, self.layer.clearance, want,
                              self.layer.lane_time, WALKING, self._refuge, turns)
        self._refuge = None if step is None else step.refuge
        if step is None or step.heading is None:
            return ZERO_TWIST
        u = step.heading
        c, s = math.cos(odom.yaw), math.sin(odom.yaw)
        return Twist(v * (c * u[0] + s * u[1]), v * (-s * u[0] + c * u[1]), 0.0)

    def _segments(self, people: list[Person], reach: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Each person now and ``reach`` seconds on (``predict_time`` when None), odom frame."""
        t = self.layer.predict_time if reach is None else reach
        odom = np.array([[p.x, p.y, p.x + p.vx * t, p.y + p.vy * t] for p in people])
        return odom[:, :2], odom[:, 2:]


def to_segments(x: np.ndarray, y: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from each point (``x``, ``y``, broadcast) to the segment ``a``-``b``."""
    ab = b - a
    n = float(ab @ ab)
    t = np.zeros(np.broadcast(x, y).shape) if n < 1e-12 else np.clip(((x - a[0]) * ab[0] + (y - a[1]) * ab[1]) / n, 0.0, 1.0)
    return np.hypot(x - a[0] - t * ab[0], y - a[1] - t * ab[1])


def to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance from ``p`` to the segment ``a``-``b``."""
    return float(to_segments(p[0], p[1], a, b))
