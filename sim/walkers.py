"""People walking the simulated greenhouse (spec/world.md ``walkers``), moved kinematically.

Each walker goes along its path at its speed, waits ``pause`` seconds at each end and walks it
back (ping-pong), from ``start`` seconds on; a path of one point is a worker who stays there.
At each end they turn round where they stand, at ``TURN_RATE``, in the last moments of their
pause (a cart swings round its pusher, sweeping what stands beside them), and walk back.
It does not yield to the robot, except that it stops while its next step would bring its body
within ``KEEP_CLEAR`` of a robot's (people do not walk into a machine; with a fleet, the one
nearest that step) and goes on when that is clear; a walker with ``yields: false`` does not even do that (the robot alone keeps clear).
Its body for that rule (and for the judges' clearance) is what it stands on the floor with at
the robot's height, its legs and its cart, or a crouching worker's one compact block
(``footprint_gap``); the robot's is the ``ROBOT_RADIUS`` circle. The motion is
advanced with the engine's ``pre_chunk`` beat (every 10 ms of sim time) from the sim's own
state only: no randomness, so the same world and seed give the same walk. ``hold`` stops and starts a walker (events).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from sim.engine import Engine
from sim.world import CART_FROM_WIDTH
from sim.world_checks import CROUCHING_MAX_WIDTH, ROBOT_RADIUS

LEG_RADIUS = 0.07
"""A leg's radius, m (``sim.greenhouse``'s walker model: legs half the width apart)."""
CART_HALF_WIDTH = CART_FROM_WIDTH / 2
"""A walker wider than twice this pushes a cart (``sim.world.Walker.pushes_cart``)."""
CART_AHEAD, CART_HALF_DEPTH = 0.45, 0.3
"""The cart's centre ahead of the walker and its half depth, m (``sim.greenhouse``)."""

CROUCH_HALF_DEPTH, CROUCH_HALF_WIDTH = 0.25, CROUCHING_MAX_WIDTH / 2
"""A crouching worker's block, half sizes along and across its heading, m: spec/world.md's
"one compact body about 0.5 x 0.6 m" (``sim.greenhouse`` builds the same block)."""

KEEP_CLEAR = 0.3
"""A walker stops while its next step would bring it this close to the robot's body, m."""

TURN_RATE = math.pi
"""How fast a walker turns round at the end of their walk, rad/s: half a turn in a second, the
last second of every generated pause (2-8 s): they stand out the pause facing the way they came,
as before (turned at arrival, a cart pusher stood facing back into the aisle, and the tracker
acted on fewer of them: test_people_bench's one world, 176 of 288 against at least 0.8). Turned in one 10 ms beat, a cart pusher's cart jumped 0.9 m from
one side of them to the other, through a robot standing beside them (safety.people seed 1, 99 s)."""


@dataclass
class _Walk:
    path: np.ndarray
    """(N, 2) waypoints."""
    lengths: np.ndarray
    """Cumulative arc length at each waypoint."""
    speed: float
    pause: float
    start: float
    half: float
    mocap: int
    s: float = 0.0
    """How far along the path it is, m."""
    forward: bool = True
    resume_at: float = 0.0
    """Standing at an end of the path until then."""
    held: bool = False
    heading: float = field(default=0.0)
    yields: bool = True
    """Stops short of the robot (spec/world.md ``yields``)."""
    crouching: bool = False
    turn_to: float | None = None
    """The heading being turned to at an end of the path (None: not turning)."""

    def at(self, s: float) -> np.ndarray:
        return np.array([np.interp(s, self.lengths, self.path[:, 0]), np.interp(s, self.lengths, self.path[:, 1])])


def footprint_gap(cx: float, cy: float, heading: float, half: float, x: float, y: float,
                  crouching: bool = False) -> float:
    """Distance from (x, y) to a walker's floor footprint: its legs (and the cart it pushes),
    the parts at the robot's height (the torso starts at 0.86 m, above the robot), for a walker
    at (cx, cy) facing ``heading`` whose shoulders are ``2 * half`` wide; a crouching worker's
    footprint is its one block. Negative inside."""
    c, s = math.cos(heading), math.sin(heading)
    dx, dy = x - cx, y - cy
    along, across = c * dx + s * dy, -s * dx + c * dy
    if crouching:
        return _box_gap(along, across, CROUCH_HALF_DEPTH, CROUCH_HALF_WIDTH)
    legs = min(math.hypot(along, across - side) for side in (half / 2, -half / 2)) - LEG_RADIUS
    if half <= CART_HALF_WIDTH:
        return legs
    return min(legs, _box_gap(along - CART_AHEAD, across, CART_HALF_DEPTH, half))


def _box_gap(u: float, v: float, hu: float, hv: float) -> float:
    """Signed distance from (u, v) to a box of half sizes (hu, hv) centred at the origin."""
    ox, oy = max(abs(u) - hu, 0.0), max(abs(v) - hv, 0.0)
    return math.hypot(ox, oy) if ox or oy else -min(hu - abs(u), hv - abs(v))


def _too_near(w: _Walk, x: float, y: float, heading: float, x0: float, y0: float, robots) -> bool:
    """Would ``w`` moved to (x, y, heading) from (x0, y0, its heading) come within ``KEEP_CLEAR``
    of the nearest machine's body, and nearer than it is?"""
    if not robots:
        return False
    gap, rx, ry = min((footprint_gap(x, y, heading, w.half, rx, ry, w.crouching) - ROBOT_RADIUS, rx, ry)
                      for rx, ry in robots)
    return gap < KEEP_CLEAR and gap < footprint_gap(x0, y0, w.heading, w.half, rx, ry, w.crouching) - ROBOT_RADIUS


class SimWalkers:
    def __init__(self, engine: Engine, walkers, robots_xy):
        """``robots_xy()``: every robot's true position (the rule needs where the machines are)."""
        self.engine, self.robots_xy = engine, robots_xy
        self._walks = {}
        for w in walkers:
            path = np.asarray(w.path, dtype=float)
            lengths = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
            body = engine.id(mujoco.mjtObj.mjOBJ_BODY, f"walker_{w.id}")
            crouching = w.posture == "crouching"
            walk = _Walk(path, lengths, w.speed or 0.0, w.pause, w.start, CROUCH_HALF_WIDTH if crouching else w.width / 2,
                         int(engine.model.body_mocapid[body]), yields=w.yields, crouching=crouching)
            if len(path) > 1:  # facing along its path; a worker who stays put faces +x
                walk.heading = math.atan2(path[1, 1] - path[0, 1], path[1, 0] - path[0, 0])
            self._walks[w.id] = walk
            self._place(walk)
        self._last: float | None = None

    def positions(self) -> dict[str, tuple[float, float, float]]:
        """Each walker's (x, y, body radius), world frame."""
        return {k: (float(p[0]), float(p[1]), w.half) for k, w in self._walks.items() for p in [w.at(w.s)]}

    def gap(self, walker: str, x: float, y: float) -> float:
        """Distance from (x, y) to what the walker stands on the floor with, m (negative inside)."""
        w = self._walks[walker]
        return float(footprint_gap(*w.at(w.s), w.heading, w.half, x, y, w.crouching))

    def hold(self, walker: str, held: bool) -> None:
        """Stop a walker where it is (True) or let it walk on (False)."""
        if walker not in self._walks:
            raise ValueError(f"the world has no walker {walker!r}")
        self._walks[walker].held = held

    def pre_chunk(self, t: float) -> None:
        dt, self._last = (0.0 if self._last is None else t - self._last), t
        if dt <= 0:
            return
        robots = self.robots_xy()
        for w in self._walks.values():
            if w.held or t < w.start or w.lengths[-1] == 0.0:
                continue  # held, not started, or a worker who stays put
            if w.turn_to is not None:  # pausing at an end, turning round in its last moments
                if t >= w.resume_at - abs(math.remainder(w.turn_to - w.heading, 2 * math.pi)) / TURN_RATE:
                    self._turn(w, dt, robots)
                continue
            if t < w.resume_at:
                continue  # pausing at an end
            step = w.speed * dt * (1 if w.forward else -1)
            s = min(max(w.s + step, 0.0), w.lengths[-1])
            (x, y), (x0, y0) = w.at(s), w.at(w.s)
            heading = math.atan2(y - y0, x - x0) if s != w.s else w.heading
            if w.yields and _too_near(w, x, y, heading, x0, y0, robots):
                continue  # the next step would come too close to the nearest machine: wait (a step away is fine)
            w.heading = heading
            w.s = s
            if s in (0.0, w.lengths[-1]) and (s == w.lengths[-1]) == w.forward:
                w.forward = not w.forward
                w.resume_at = t + w.pause
                w.turn_to = math.remainder(w.heading + math.pi, 2 * math.pi)
            self._place(w)

    def _turn(self, w: _Walk, dt: float, robots) -> None:
        """Turn ``w`` round where they stand, ``TURN_RATE`` at most this beat (one who yields waits
        while the swing would bring them too close to a machine)."""
        left = math.remainder(w.turn_to - w.heading, 2 * math.pi)
        done = abs(left) <= TURN_RATE * dt
        heading = w.turn_to if done else w.heading + math.copysign(TURN_RATE * dt, left)
        x, y = w.at(w.s)
        if w.yields and _too_near(w, x, y, heading, x, y, robots):
            return
        w.heading = heading
        if done:
            w.turn_to = None
        self._place(w)

    def _place(self, w: _Walk) -> None:
        d = self.engine.data
        x, y = w.at(w.s)
        d.mocap_pos[w.mocap] = (x, y, 0.0)
        d.mocap_quat[w.mocap] = (math.cos(w.heading / 2), 0.0, 0.0, math.sin(w.heading / 2))
