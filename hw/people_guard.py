"""The people guard: issue 28's speed rules near people, on every twist the mux lets through.

"At most 0.15 m/s within 1.0 m of a person; never drive towards a person nearer than 0.5 m."
The costmaps' person layer makes navigation plan and drive round people; these rules hold for
every source (autonomy, console, gamepad), so they sit where the collision monitor sits: between
the twist_mux and the wheels, judged on the base controller's beat. In order:

1. the e-stop, checked by the base controller before any guard (unchanged);
2. this guard: with a person (``hw.people.Person``, at least ``min_confidence``) nearer than
   ``still_distance`` body to body the base does not move at all for ``still_wait`` (they came
   to it: wait them out), then only sideways or away; nearer than ``slow_distance``, the whole twist is scaled so the linear speed is at most
   ``slow_speed`` (the path's curvature kept, as the monitor's slowdown does); then, for every
   person nearer than ``near_distance``, the component of the linear motion towards them is
   removed (sideways and away still pass; turning on the spot sweeps nothing with a circular
   footprint). "Towards" is towards the person's centre and towards the nearest of the scan's
   returns on their body (``returns``): a cart is long, and a step away from its middle can be
   a step towards its corner (safety.people, seed 111 at 2,019 s: a robot stepping away from a
   cart's track centre came 0.15 m from the cart's front corner). Ringed round by people that
   near, where every motion closes on one of them, a creep of at most ``ring_closing`` towards
   anyone passes (``escape``);
3. ``below``, the collision monitor: its geometric stop zone on the raw scan stays the last
   line, and nothing here can switch it off (a person the tracker missed or got wrong is still
   an obstacle to it).

The guard only ever scales or removes motion, never adds or turns any. People come as data
(``hw.people.PeopleSource``, odom frame, read each tick) with the robot's odom pose: ``hw``
never imports perception, the runtime hands the tracker's tracks in. Body to body is from the
footprint circle (``nav.costmap.robot_radius``, passed in) to the person's radius.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from hw.config import PeopleGuardConfig
from hw.interfaces import Twist
from hw.odometry import Pose2D
from hw.people import PeopleSource, nobody

#: Below this linear speed (m/s) the base only turns: nothing to judge.
MOVING = 1e-3

BODY_MARGIN = 0.1
"""A return this far outside a person's circle (m) is still on their body: the circle is the
tracker's, a scan late and smoothed, and a cart's corner sits at its edge."""


def no_returns() -> np.ndarray:
    """The returns source with no scan: the people's circles alone."""
    return np.empty((0, 2))


NONE, SLOW, AWAY, STILL = "none", "slow", "away", "still"


class TwistGuard(Protocol):
    def filter(self, twist: Twist, now: float) -> Twist: ...


@dataclass(frozen=True)
class PeopleVerdict:
    """What the guard did to one twist, and why."""

    action: str
    """``none``, ``slow`` (capped near a person) or ``away`` (motion towards a near person removed)."""
    scale: float
    """Linear speed let through over the speed commanded (1 untouched, 0 none of it)."""
    nearest: float
    """Body-to-body distance to the nearest person, m (inf: nobody)."""

    @property
    def holding(self) -> bool:
        """The base is kept from driving where it was told (nearly all its motion removed)."""
        return self.action == STILL or (self.action == AWAY and self.scale < 0.1)


CLEAR = PeopleVerdict(NONE, 1.0, math.inf)


class PeopleGuard:
    def __init__(self, config: PeopleGuardConfig, pose: Callable[[], Pose2D], footprint_radius: float,
                 people: PeopleSource = nobody, below: TwistGuard | None = None,
                 returns: Callable[[], np.ndarray] = no_returns):
        self.config = config
        self.pose = pose
        """The robot's odom pose (wheel odometry): the frame people come in."""
        self.radius = footprint_radius
        self.people = people
        """The tracker's people; ``hw.people.nobody`` until a tracker runs."""
        self.below = below
        """The next guard down (the collision monitor), handed what this one lets through."""
        self.returns = returns
        """The last scan's returns, base frame, (N, 2) (the collision monitor's, the robot's own
        outline taken out): where a person's body really is, inside the tracker's circle."""
        self.verdict = CLEAR
        """The last twist's verdict."""
        self._still_since: float | None = None
        """Since when someone has been at arm's length (``still_distance``)."""

    def filter(self, twist: Twist, now: float) -> Twist:
        out = self.judge(twist, now)
        return self.below.filter(out, now) if self.below is not None else out

    def judge(self, twist: Twist, now: float = 0.0) -> Twist:
        """The twist the people rules allow (``filter`` without what lies below) at ``now``."""
        speed = math.hypot(twist.vx, twist.vy)
        rel = self._relative()
        near = self._near(rel)
        soon = self._soonest_gap(rel)
        close = soon < self.config.still_distance
        if not close:
            self._still_since = None
        elif self._still_since is None:
            self._still_since = now
        if close and (speed >= MOVING or twist.wz) and now - self._still_since < self.config.still_wait:
            self.verdict = PeopleVerdict(STILL, 0.0, float(near[1].min()) if near is not None else soon)
            return Twist(0.0, 0.0, 0.0)
        if speed < MOVING or near is None:
            self.verdict = CLEAR if near is None else PeopleVerdict(NONE, 1.0, float(near[1].min()))
            return twist
        toward, gap = near
        c = self.config
        action, v, wz = NONE, np.array([twist.vx, twist.vy]), twist.wz
        if gap.min() < c.slow_distance and speed > c.slow_speed:
            s = c.slow_speed / speed
            action, v, wz = SLOW, v * s, wz * s
        close = toward[gap < c.near_distance]
        if len(close) and not (float((close @ v).max()) <= c.ring_closing + 1e-9 and _ringed(close)):
            before = float(np.hypot(*v))
            v = _without_towards(v, close)
            action = AWAY if float(np.hypot(*v)) < before - 1e-9 else action
        scale = float(np.hypot(*v)) / speed
        self.verdict = PeopleVerdict(action, scale, float(gap.min()))
        return twist if action == NONE else Twist(float(v[0]), float(v[1]), wz)

    def escape(self, speed: float) -> Twist:
        """A step away from everyone nearer than ``near_distance`` (their centres and the
        nearest returns on their bodies, as ``judge`` reads them), base frame, at ``speed``;
        zero with nobody that near. The navigator takes it when its own step out of the way has
        been held here for a while: its refuge is chosen on the tracks' circles, and between two
        people a step the circles allow can close on a cart's corner that the returns show
        (safety.people seed 113 at 675 s: a standing worker on one side, a cart that yields on
        the other, the robot held still between them for 2,400 s while the cart waited for it).
        The step heads down the middle of the widest way between them, which closes on none of
        them if it is at least a half turn wide; ringed round, it closes on the people either
        side of that way at most ``ring_closing``, the creep ``judge`` lets through there."""
        near = self._near(self._relative())
        if near is None:
            return Twist(0.0, 0.0, 0.0)
        toward, gap = near
        close = toward[gap < self.config.near_distance]
        if not len(close):
            return Twist(0.0, 0.0, 0.0)
        heading, width = _widest_way(close)
        closing = math.cos(width / 2)  # the share of the step towards the people either side
        if closing > 0.0:
            speed = min(speed, self.config.ring_closing / closing)
        return Twist(speed * math.cos(heading), speed * math.sin(heading), 0.0)

    def _relative(self) -> np.ndarray:
        """The people that count, read once a tick: (P, 5) rows of their offset from the robot
        (odom axes), velocity and radius."""
        r = self.pose()
        return np.array([[p.x - r.x, p.y - r.y, p.vx, p.vy, p.radius] for p in self.people()
                         if p.confidence >= self.config.min_confidence]).reshape(-1, 5)

    def _soonest_gap(self, rel: np.ndarray) -> float:
        """The least body-to-body distance to anyone, now or where their walk takes them within
        ``still_lookahead`` (a grower crossing at 0.8 m/s closes 0.08 m per base tick, and the
        tracker sees them a scan late); inf with nobody about. Someone walking straight at the
        robot counts too: once they are that close a step aside (0.15 m/s within 1 m) cannot
        clear their way before they arrive, and moving beside them is the robot's doing, where
        being walked into standing still is theirs. Getting out of a walker's way is the
        navigator's, while they are still metres off (``nav.refuge``). Such a walker used to be
        stepped away from here: in safety.people's traces (seed 1 at 116 s) the step ended with
        a cart that does not yield 0.17 m into the body of a robot still moving."""
        if not len(rel):
            return math.inf
        t = np.linspace(0.0, self.config.still_lookahead, 4)
        x = rel[:, None, 0] + rel[:, None, 2] * t
        y = rel[:, None, 1] + rel[:, None, 3] * t
        return float((np.hypot(x, y) - rel[:, None, 4]).min() - self.radius)

    def _near(self, rel: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """Unit directions (base frame, (K, 2)) to the people that count, and body-to-body
        distances: one row per person to their centre, and one to the nearest return on each
        person's body that has one (that return's distance); None with nobody about. A person's
        centre row is as far as their circle says, or as their nearest return when the scan
        shows their body farther off: the tracker's circle is a scan late and round, and a
        worker's legs 0.58 m off whose circle came to 0.47 m closed the only way out between
        them and a cart (safety.people seed 113 at 681 s, held 2,400 s)."""
        if not len(rel):
            return None
        yaw = self.pose().yaw
        c, s = math.cos(yaw), math.sin(yaw)
        base = rel[:, :2] @ np.array([[c, -s], [s, c]])  # world -> base: rotate by -yaw
        gap = np.hypot(base[:, 0], base[:, 1]) - rel[:, 4]
        seen, body = self._nearest_returns(base, rel[:, 4])
        reach = np.hypot(body[:, 0], body[:, 1])
        gap[seen] = np.maximum(gap[seen], reach)
        at = np.concatenate([base, body])
        dist = np.maximum(np.hypot(at[:, 0], at[:, 1]), 1e-9)
        return at / dist[:, None], np.concatenate([gap, reach]) - self.radius

    def _nearest_returns(self, centres: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The people (indices into the base-frame ``centres``) with returns within their circle
        and ``BODY_MARGIN``, and the nearest of those returns to the robot for each, (<= P, 2)."""
        pts = np.asarray(self.returns(), dtype=float).reshape(-1, 2)
        if not len(pts):
            return np.empty(0, dtype=int), np.empty((0, 2))
        on = np.hypot(*(pts[None, :, :] - centres[:, None, :]).transpose(2, 0, 1)) <= (radii + BODY_MARGIN)[:, None]
        far = np.where(on, np.hypot(pts[:, 0], pts[:, 1])[None, :], np.inf)
        k = np.argmin(far, axis=1)
        seen = np.flatnonzero(np.isfinite(far[np.arange(len(k)), k]))
        return seen, pts[k[seen]]


def _widest_way(toward: np.ndarray) -> tuple[float, float]:
    """The middle of the widest way between the unit directions ``toward`` (base frame, rad)
    and that way's width (rad, 2 pi for one direction)."""
    angles = np.sort(np.arctan2(toward[:, 1], toward[:, 0]))
    gaps = np.diff(np.append(angles, angles[0] + 2 * math.pi))
    k = int(np.argmax(gaps))
    return float(angles[k] + gaps[k] / 2), float(gaps[k])


def _ringed(toward: np.ndarray) -> bool:
    """Does every way close on one of the unit directions ``toward`` (none a half turn wide)?"""
    return _widest_way(toward)[1] < math.pi - 1e-9


def _without_towards(v: np.ndarray, toward: np.ndarray) -> np.ndarray:
    """The motion nearest ``v`` that closes on none of the unit directions ``toward``: ``v``'s
    projection on that cone of motions. In the plane the cone's edges lie on lines square to
    some of the directions, so the answer is ``v`` itself, its projection on one such line, or
    no motion. Until stop 61 the components were taken out in turn, two rounds, and what still
    closed on someone stopped: on 20,000 random cases of two and three people that came to the
    same motion; this finds it directly and says what it is."""
    def closes(w: np.ndarray) -> bool:
        return bool(np.any(toward @ w > 1e-9))

    if not closes(v):
        return v
    best, cut = np.zeros(2), float(np.hypot(*v))
    for u in toward:
        along = float(v @ u)
        w = v - along * u
        if abs(along) < cut and not closes(w):
            best, cut = w, abs(along)
    return best
