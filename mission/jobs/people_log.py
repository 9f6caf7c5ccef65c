"""How close the robot came to each walker while it moved, every time it touched one while it
moved, and every time a walker came within 1.0 m of it: ground truth, for the scenario judge
(``expect.people``, spec/scenario.md) and ``lupin bench safety.people``.

Sampled by the simulator before every physics chunk (10 ms: at 1 m/s a walker and the robot
close in by at most ~2 cm between samples). Clearance is body to body at the robot's height:
from the robot's body, its footprint circle (``ROBOT_RADIUS``) and the arm as it stands (its
links from the pan axis through elbow and wrist to the wrist camera, seen from above and
thickened by ``ARM_RADIUS``: reaching out at ``inspect`` it passes the footprint), to the
walker's legs, cart or crouching block (``sim.walkers.footprint_gap``). The spec judges only
the moments the robot moves (true base speed >= ``MOVING_SPEED`` or turn rate >= ``MOVING_TURN``
over the last ``SPEED_WINDOW``) under its own drive (``driving``: its base's wheel
reference non-zero within the last ``COAST``): a walker that walks into a robot standing still is
not the robot's doing, nor is a cart pusher who walks on and shoves it along the floor (by truth
alone a shoved robot "moved", and safety.people counted the carts' shoves as the robot's). A contact is an onset of a walker geom touching the chassis (``ContactLog``),
counted when the robot moved at its onset. An encounter is a stretch of a walker within
``NEAR`` (body to body, moving or not), closed once it has stayed beyond for ``GAP`` seconds;
with ``withheld`` (the collision monitor's withheld share of the speed, 0..1) each encounter
also carries ``lost_s``, that share integrated while it lasted. Judging only: nothing steers by it.
"""
from __future__ import annotations

import math
from collections import deque
from typing import Callable

import numpy as np

from arm.config import KinematicsConfig
from arm.kinematics import planar
from arm.presets import ARM_JOINTS
from mission.jobs.contacts import ContactLog
from mission.patrol.monitor_holds import GAP
from mission.patrol.person_encounters import NEAR
from sim.backend import SimRobot
from sim.world_checks import ROBOT_RADIUS

MOVING_SPEED, MOVING_TURN = 0.05, 0.1
"""The robot moves at or above these, m/s and rad/s (spec/scenario.md ``people.min_clearance``)."""
SPEED_WINDOW = 0.1
"""Speeds are taken over this much sim time, s (ten 10 ms samples: a chassis' contact jitter
between two samples is not motion)."""
COAST = 0.5
"""A robot whose wheels were told to turn this recently still moves of its own accord, s: the
base brakes from its crawl near people within a few of its 10 Hz ticks."""
ARM_RADIUS = 0.03
"""Half the arm links' width seen from above, m (robot model: the gripper servo 0.036 m wide,
rounded up)."""
ARM_STEP = 0.03
"""Spacing of the points the arm's links are sampled at, m."""


def arm_points(q, k: KinematicsConfig) -> np.ndarray:
    """(N, 2) points along the arm's links seen from above, base frame, for joint angles ``q``
    (shoulder_pan, shoulder_lift, elbow, wrist): pan axis -> elbow -> wrist -> wrist camera
    (the chain and its signs as ``arm.kinematics``)."""
    pan, q1, q2, q3 = (float(v) for v in q)
    t1 = -q1
    t2 = t1 + q2
    elbow = k.upper_arm * math.sin(t1)
    wrist = elbow + k.forearm * math.sin(t2)
    camera = planar(q1, q2, q3, k, math)[0]
    reach = np.concatenate([np.linspace(a, b, max(2, int(abs(b - a) / ARM_STEP) + 2))
                            for a, b in ((0.0, elbow), (elbow, wrist), (wrist, camera))])
    return np.asarray(k.pan_origin[:2]) + reach[:, None] * np.array([math.cos(pan), math.sin(pan)])


class PeopleLog:
    def __init__(self, sim: SimRobot, kinematics: KinematicsConfig = KinematicsConfig(),
                 withheld: Callable[[], float] | None = None, driving: Callable[[], bool] | None = None):
        self.sim, self.kinematics, self.withheld, self.driving = sim, kinematics, withheld, driving
        self._drove = -math.inf
        self.contacts = ContactLog(lambda: [n for n in sim.touching() if n.startswith("walker_")])
        self.moving_contacts: list[tuple[float, str]] = []
        """(sim time, geom) of each contact that began while the robot moved."""
        self.min_clearance: dict[str, float] = {w.id: math.inf for w in sim.world.walkers}
        """Per walker, the least body-to-body distance seen while the robot moved, m."""
        self.close_at: dict[str, tuple[float, float, float]] = {}
        """Per walker, (sim time, x, y) of the robot when it came closest while moving."""
        self.least_any = math.inf
        """The least clearance at any moment, the robot standing included (for the record)."""
        self.encounters: list[dict] = []
        """Every walker within ``NEAR``: walker, t (sim time), x, y (robot), nearest_m (at any moment),
        nearest_moving_m (while the robot moved; None: it stood throughout), moving_at (sim time,
        robot x, y of that least while moving; None with it), lost_s."""
        self._open: dict[str, dict] = {}
        self._trail: deque[tuple[float, float, float, float]] = deque()
        self._last: float | None = None

    def attach(self) -> "PeopleLog":
        if self.min_clearance:
            self.sim.engine.attach(self)
        return self

    def pre_chunk(self, t: float) -> None:
        dt, self._last = (0.0 if self._last is None else t - self._last), t
        robot = self.sim.truth()
        moving = self._moving(t, robot.x, robot.y, robot.yaw)
        withheld = self.withheld() if self.withheld is not None and self._open else 0.0
        arm = None
        for walker in self.min_clearance:
            gap = self.sim.walkers.gap(walker, robot.x, robot.y) - ROBOT_RADIUS
            if gap < NEAR:  # the arm reaches at most ~0.3 m past the footprint: only near people
                arm = self._arm_world(robot) if arm is None else arm
                gap = min(gap, min(self.sim.walkers.gap(walker, x, y) for x, y in arm) - ARM_RADIUS)
            self.least_any = min(self.least_any, gap)
            if moving and gap < self.min_clearance[walker]:
                self.min_clearance[walker] = gap
                self.close_at[walker] = (t, robot.x, robot.y)
            self._encounter(walker, gap, moving, t, dt, robot.x, robot.y, withheld)
        before = len(self.contacts.onsets)
        self.contacts.sample(t)
        if moving:
            self.moving_contacts += self.contacts.onsets[before:]

    def _moving(self, t: float, x: float, y: float, yaw: float) -> bool:
        self._trail.append((t, x, y, yaw))
        while self._trail[0][0] < t - SPEED_WINDOW - 1e-9:
            self._trail.popleft()
        t0, x0, y0, yaw0 = self._trail[0]
        if self.driving is None or self.driving():
            self._drove = t
        if t - t0 < SPEED_WINDOW / 2 or t - self._drove > COAST:
            return False
        turn = abs(math.atan2(math.sin(yaw - yaw0), math.cos(yaw - yaw0)))
        return math.hypot(x - x0, y - y0) >= MOVING_SPEED * (t - t0) or turn >= MOVING_TURN * (t - t0)

    def _arm_world(self, robot) -> list[tuple[float, float]]:
        q = [self.sim.servos.joint_position(j) for j in ARM_JOINTS]
        p = arm_points(q, self.kinematics)
        c, s = math.cos(robot.yaw), math.sin(robot.yaw)
        return list(zip(robot.x + c * p[:, 0] - s * p[:, 1], robot.y + s * p[:, 0] + c * p[:, 1]))

    def _encounter(self, walker: str, gap: float, moving: bool, t: float, dt: float, x: float, y: float,
                   withheld: float) -> None:
        e = self._open.get(walker)
        if e is not None:
            e["lost_s"] += dt * withheld
        if gap < NEAR:
            if e is None:
                e = self._open[walker] = {"walker": walker, "t": t, "x": x, "y": y, "nearest_m": gap,
                                          "nearest_moving_m": None, "moving_at": None, "lost_s": 0.0}
                self.encounters.append(e)
            e["nearest_m"], e["_near"] = min(e["nearest_m"], gap), t
            if moving and (e["nearest_moving_m"] is None or gap < e["nearest_moving_m"]):
                e["nearest_moving_m"], e["moving_at"] = gap, (t, x, y)
        elif e is not None and t - e["_near"] >= GAP:
            del self._open[walker]

    @property
    def clearance(self) -> float:
        """The least clearance to any walker while the robot moved (inf: no walkers, or never)."""
        return min(self.min_clearance.values(), default=math.inf)

    def as_json(self) -> dict:
        return {"min_clearance_m": None if math.isinf(self.clearance) else round(self.clearance, 3),
                "least_standing_or_moving_m": None if math.isinf(self.least_any) else round(self.least_any, 3),
                "contacts": len(self.moving_contacts), "contacts_standing_or_moving": len(self.contacts.onsets),
                "encounters": len(self.encounters),
                "walkers": {k: round(v, 3) for k, v in self.min_clearance.items() if not math.isinf(v)}}
