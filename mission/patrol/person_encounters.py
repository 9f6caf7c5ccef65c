"""Person encounters: each time a person the robot's own tracker follows came within ``NEAR`` of
the robot, for the report's ``people`` list (spec/report.md: where, how long the robot waited and
drove slowed meanwhile, and how close the person came).

The robot cannot know ground truth, so a person here is what its tracker hands down as a
``hw.people.Person`` (a ``PeopleSource``, odom frame) and the distance is body to body: from the
person's circle to the robot's footprint circle, both in odom (a SLAM correction never makes a
person jump). An encounter opens when a track comes within ``NEAR`` and closes once it has
stayed beyond it for ``monitor_holds.GAP`` seconds; waiting and slowing are the collision
monitor's stop and slowdown while it is open, whatever their cause. The monitor's holds for pots
and walls are a different list (``mission.patrol.monitor_holds``, the report's ``holds``):
issue 28 found every hold counted as a person. With ``hw.people.nobody`` as the source (no
tracker) the list stays empty.
"""
from __future__ import annotations

from typing import Callable

from hw.collision_monitor import NONE, Verdict
from hw.odometry import Pose2D
from hw.people import PeopleSource
from mission.patrol.monitor_holds import GAP

NEAR = 1.0
"""Body-to-body distance that makes an encounter, m (spec/report.md: a walker within 1.0 m)."""


class PersonEncounters:
    def __init__(self, people: PeopleSource, pose: Callable[[], Pose2D], verdict: Callable[[], Verdict], t0: float,
                 footprint_radius: float = 0.22):
        """``people``: the tracker's people, odom frame; ``pose``: the robot's odom pose;
        ``verdict``: the collision monitor's latest; ``t0``: the mission's start (the report's
        times count from it); ``footprint_radius``: the robot's body (nav's footprint circle)."""
        self.people, self.pose, self.verdict, self.t0, self.radius = people, pose, verdict, t0, footprint_radius
        self.done: list[dict] = []
        self._open: dict[int, dict] = {}
        self._near_at: dict[int, float] = {}
        self._last: float | None = None

    def tick(self, now: float) -> None:
        dt, self._last = (0.0 if self._last is None else now - self._last), now
        p = self.pose()
        v = self.verdict()
        for person in self.people():
            gap = person.gap(p.x, p.y, self.radius)
            if gap >= NEAR:
                continue
            if person.id not in self._open:
                self._open[person.id] = {"t": round(now - self.t0, 2), "x": round(p.x, 2), "y": round(p.y, 2),
                                         "person": person.id, "waited_s": 0.0, "slowed_s": 0.0, "nearest_m": gap}
            e = self._open[person.id]
            e["nearest_m"] = min(e["nearest_m"], gap)
            self._near_at[person.id] = now
        for key, e in list(self._open.items()):
            if v.action != NONE:
                e["waited_s" if v.holding else "slowed_s"] += dt
            if now - self._near_at[key] >= GAP:
                self.done.append(self._shown(self._open.pop(key)))

    @staticmethod
    def _shown(e: dict) -> dict:
        return {**e, "waited_s": round(e["waited_s"], 2), "slowed_s": round(e["slowed_s"], 2),
                "nearest_m": round(max(e["nearest_m"], 0.0), 3)}

    # -- the report observer -------------------------------------------------------------------
    def recorded(self, pot, entry: dict, kinds: list[str]) -> None:
        pass

    def sections(self) -> dict:
        """``people``: every encounter so far, those in progress included."""
        return {"people": self.done + [self._shown(e) for e in self._open.values()]}

    def finished(self, doc: dict) -> None:
        pass
