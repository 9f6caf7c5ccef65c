"""How close the robot came to each walker, and every time it touched one: ground truth, for
the scenario judge (``expect.people``) and ``lupin bench safety.people``.

Sampled by the simulator before every physics chunk (10 ms: at 1 m/s a walker and the robot
close in by at most ~2 cm between samples). Clearance is body to body at the robot's height:
from the robot's footprint circle to the walker's legs (and the cart it pushes), which is what
the lidar sees of a person and what the robot could touch (``sim.walkers.footprint_gap``). A contact is an onset of a walker geom touching the chassis (``ContactLog``). Judging
only: nothing steers by it.
"""
from __future__ import annotations

import math

from mission.jobs.contacts import ContactLog
from sim.backend import SimRobot
from sim.world_checks import ROBOT_RADIUS


class PeopleLog:
    def __init__(self, sim: SimRobot):
        self.sim = sim
        self.contacts = ContactLog(lambda: [n for n in sim.touching() if n.startswith("walker_")])
        self.min_clearance: dict[str, float] = {w.id: math.inf for w in sim.world.walkers}
        """Per walker, the least body-to-body distance seen, m."""
        self.close_at: dict[str, tuple[float, float, float]] = {}
        """Per walker, (sim time, x, y) of the robot when it came closest."""

    def attach(self) -> "PeopleLog":
        if self.min_clearance:
            self.sim.engine.attach(self)
        return self

    def pre_chunk(self, t: float) -> None:
        robot = self.sim.truth()
        for walker in self.min_clearance:
            gap = self.sim.walkers.gap(walker, robot.x, robot.y) - ROBOT_RADIUS
            if gap < self.min_clearance[walker]:
                self.min_clearance[walker] = gap
                self.close_at[walker] = (t, robot.x, robot.y)
        self.contacts.sample(t)

    @property
    def clearance(self) -> float:
        """The least clearance to any walker over the run (inf: no walkers)."""
        return min(self.min_clearance.values(), default=math.inf)

    def as_json(self) -> dict:
        return {"min_clearance_m": None if math.isinf(self.clearance) else round(self.clearance, 3),
                "contacts": len(self.contacts.onsets),
                "walkers": {k: round(v, 3) for k, v in self.min_clearance.items() if not math.isinf(v)}}
