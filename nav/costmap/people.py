"""The person layer: tracked people kept at a distance (issue 28 item 2), as Nav2's social
costmap layers (nav2_social_costmap_plugin) do it: costs round each person written over the
inflated master, so the planner goes round people and MPPI keeps away from them, while pots,
benches and walls keep the inflation's distances (the person rules apply to people only).

Per person (``hw.people.Person``, at least ``min_confidence``) at distance d from its centre,
with ``keep_out = radius + clearance + robot_radius``:

    d <= keep_out                    254 lethal: the robot's centre here puts its body within
                                     ``clearance`` (0.3 m) of the person's
    d <= keep_out + gradient         int(252 exp(-k (d - keep_out))), the inflation's falloff
    along the predicted stretch      the same profile round the segment the person walks in the
                                     next ``predict_time`` s: the robot does not step into a
                                     walker's way (one who does not yield walks on into it);
                                     for someone paused, their last walk's stretch both ways
                                     (``nav.walks``): they walk back the way they came, or on;
                                     in the planner's costmap (``whole_walk_back``) all of
                                     their last walk back to where it began

The layer comes after inflation, not before: its keep-out already counts the robot's inscribed
radius, and inflating a person's disc would add the 0.22 m again. A cell the master does not
know (255) is taken over only by the lethal disc: a person is seen there, the rest stays
unexplored. People come in ``odom`` (``hw.people``); ``frame`` gives odom's pose in this costmap's
frame (the identity for the local costmap, ``map -> odom`` for the global one).

Why a paused walker's way both ways: safety.people seed 2, 1,472 s: a cart pusher who does not
yield paused at the north end of their cross aisle; the robot, 1.1 m from them, crossed that
aisle at its 0.15 m/s (within 1 m of a person), and they turned and walked back down it, into
the robot and on, shoving it 3.5 m south. Kept out of their way back, the robot waits at its edge
and crosses behind them.

Cost: a window of at most ~(2 (keep_out + gradient + speed * predict_time) / resolution)^2
cells per person, vectorised; nothing at all with nobody about.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Sequence

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person, PeopleSource, nobody
from nav.costmap.config import PersonLayerConfig
from nav.costmap.grid import INSCRIBED, LETHAL, UNKNOWN
from nav.frames import compose
from nav.grid_geometry import GridGeometry
from nav.walks import walks_of

#: The highest cost below inscribed: the falloff's start.
HIGHEST = INSCRIBED - 1


class PersonLayer:
    def __init__(self, config: PersonLayerConfig, robot_radius: float, cost_scaling_factor: float,
                 people: PeopleSource = nobody, frame: Callable[[], Pose2D] = Pose2D):
        self.config = config
        self.robot_radius = robot_radius
        self.k = cost_scaling_factor
        self.people = walks_of(people)
        """The tracker's people (odom frame), read at every rebuild, their walks remembered."""
        self.frame = frame
        """odom's pose in this costmap's frame."""

    def keep_out(self, person: Person) -> float:
        """Centre-to-centre distance inside which the robot would be closer than ``clearance``."""
        return person.radius + self.config.clearance + self.robot_radius

    def present(self) -> list[Person]:
        """The people that count, in this costmap's frame."""
        seen = [p for p in self.people() if p.confidence >= self.config.min_confidence]
        if not seen:
            return []
        t = self.frame()
        c, s = np.cos(t.yaw), np.sin(t.yaw)
        out = []
        for p in seen:
            q = compose(t, Pose2D(p.x, p.y, 0.0))
            out.append(Person(p.id, q.x, q.y, c * p.vx - s * p.vy, s * p.vx + c * p.vy, p.radius, p.confidence))
        return out

    def apply(self, master: np.ndarray, geometry: GridGeometry) -> np.ndarray:
        """``master`` (inflated costs) with every present person's costs over it; the same array
        when nobody is about, else a new one."""
        people = self.present()
        if not people:
            return master
        out = master.copy()
        yaw = self.frame().yaw
        c, s = np.cos(yaw), np.sin(yaw)
        for p in people:
            self._stamp(out, geometry, p)
            walk = self.people.paused(p)
            if walk is not None:  # their way back and on, each a walker's predicted stretch
                vx, vy = c * walk[0] - s * walk[1], s * walk[0] + c * walk[1]
                for sign in (-1.0, 1.0):
                    self._stamp(out, geometry, replace(p, vx=sign * vx, vy=sign * vy))
                back = self.people.way_back(p) if self.config.whole_walk_back else None
                if back is not None and self.config.predict_time > 0.0:  # a stretch is velocity x predict_time
                    t = self.config.predict_time
                    self._stamp(out, geometry, replace(p, vx=(c * back[0] - s * back[1]) / t,
                                                       vy=(s * back[0] + c * back[1]) / t))
        return out

    def costs(self, geometry: GridGeometry, person: Person) -> tuple[tuple[slice, slice], np.ndarray]:
        """The cells round ``person`` (a window of the grid) and the layer's costs there."""
        cfg, res = self.config, geometry.resolution
        r = self.keep_out(person)
        vx, vy = person.vx * cfg.predict_time, person.vy * cfg.predict_time
        reach = r + cfg.gradient
        ix, iy = geometry.cell_of(np.array([person.x + min(0.0, vx) - reach, person.x + max(0.0, vx) + reach]),
                                  np.array([person.y + min(0.0, vy) - reach, person.y + max(0.0, vy) + reach]))
        w, h = geometry.width, geometry.height
        x0, x1 = max(0, int(ix[0])), min(w, int(ix[1]) + 1)
        y0, y1 = max(0, int(iy[0])), min(h, int(iy[1]) + 1)
        if x0 >= x1 or y0 >= y1:
            return (slice(0, 0), slice(0, 0)), np.zeros((0, 0), dtype=np.uint8)
        cx, cy = geometry.centre_of(np.arange(x0, x1)[None, :], np.arange(y0, y1)[:, None])
        dx, dy = cx - person.x, cy - person.y
        cost = self._profile(np.hypot(dx, dy), r)
        span = vx * vx + vy * vy
        if span > (res * res):
            t = np.clip((dx * vx + dy * vy) / span, 0.0, 1.0)
            ahead = self._profile(np.hypot(dx - t * vx, dy - t * vy), r)
            cost = np.maximum(cost, ahead)
        return (slice(y0, y1), slice(x0, x1)), cost

    def _profile(self, d: np.ndarray, keep_out: float) -> np.ndarray:
        past = d - keep_out
        fall = (HIGHEST * np.exp(-self.k * np.maximum(past, 0.0))).astype(np.int64)
        cost = np.where(past <= 0.0, LETHAL, np.where(past <= self.config.gradient, fall, 0))
        return cost.astype(np.uint8)

    def _stamp(self, out: np.ndarray, geometry: GridGeometry, person: Person) -> None:
        window, cost = self.costs(geometry, person)
        m = out[window]
        known = m != UNKNOWN
        out[window] = np.where(known, np.maximum(m, cost), np.where(cost == LETHAL, LETHAL, m))


def keep_outs(layer: PersonLayer | None) -> Sequence[tuple[float, float, float]]:
    """(x, y, keep_out) of each present person in the layer's frame (none without a layer)."""
    if layer is None:
        return ()
    return [(p.x, p.y, layer.keep_out(p)) for p in layer.present()]
