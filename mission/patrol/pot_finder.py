"""Pots found where they are, not where the mission says: their tags place them.

At each pot the tag read at arrival gives the pot's pose (``mission.patrol.tag_sightings``).
Off the mission's pose by more than ``moved_xy`` / ``moved_yaw`` (beyond the map's local drift
from the mission's frame, ``mission.patrol.map_drift``), the pot has moved: the robot
approaches it again from where it is (the approach pose and the wrist's aim follow the tag), and
the report says ``moved`` with the measured pose. With no tag at all where the pot should be, the
pots the SLAM map shows within ``search_radius`` of the mission's position are looked at from
each side the robot fits, nearest first, until the pot's tag turns up; only then is the pot
``not_found``. A different tag at the pot is a swapped or re-labelled pot: a ``tag_mismatch``
for the operator, not something to search past.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from behaviours.visit import PotVisit
from hw.odometry import Pose2D
from mission.approach import approach_pose
from mission.patrol.config import PatrolConfig
from mission.patrol.map_drift import Drift, MapDrift, corrections, in_mission_frame, walls_apart
from mission.patrol.mission_file import Mission, MissionPot
from mission.patrol.tag_sightings import pot_from_tag
from nav.costmap.grid import INSCRIBED
from nav.frames import compose
from nav.navigator import Navigator
from nav.viewpoints import looks, pot_blobs
from perception.detections import TagRead


SEARCH_BACK = 0.2
"""Metres the search first steps back along the robot's heading, and farther the second ring of
looks stands."""
SLANTS = (0.25, 0.5)
"""Radians off square a search looks at a pot from where the robot does not fit square on to it
(``nav.viewpoints.looks``): a pot pushed 0.18 m into a 0.8 m aisle and turned 0.24 rad (the
30 m two-bay greenhouse's P18) left no look square in front of it, the pot across the aisle in
the way; at 0.25-0.5 rad its plate is still read well within the reader's angle."""


@dataclass
class PotFinder:
    mission: Mission
    nav: Navigator
    config: PatrolConfig
    drift: MapDrift = field(init=False)
    """The map's drift from the mission's frame, read off the pots located so far."""

    def __post_init__(self):
        self.drift = MapDrift(self.config.drift_radius, self.config.moved_xy / 2)
        self.drift.epoch = lambda: corrections(self.nav.localisation if self.nav else None)

    def own_tag(self, pot: MissionPot, reads: tuple[TagRead, ...], reach: float) -> TagRead | None:
        """The pot's own tag among ``reads``, read no farther than ``reach``."""
        return next((r for r in reads if r.id == pot.tag and r.distance <= reach), None)

    def needs_search(self, pot: MissionPot, visit: PotVisit) -> bool:
        """No tag at all read where the pot should be (and the mission says which to look for)."""
        near = self.config.tag_max_distance
        return pot.tag is not None and not any(r.distance <= near for r in visit.tags)

    def place(self, pot: MissionPot, visit: PotVisit, reads: tuple[TagRead, ...], robot: Pose2D, reach: float) -> bool:
        """Put the pot where its tag in ``reads`` says (robot: the map pose of the frame); True when
        it was there. Marks the visit moved when that is far enough from the mission's pose."""
        read = self.own_tag(pot, reads, reach)
        if read is None:
            return False
        s = pot_from_tag(read, robot, self.config.front_camera_mount, self.config.plate_offset)
        visit.located, visit.own_tag = (s.x, s.y, s.facing), read
        self.drift.apart = walls_apart(getattr(self.nav.localisation, "occupancy", None) if self.nav else None)
        self._judge(pot, visit, self.drift.consensus(pot.x, pot.y))
        self.drift.record((pot.x, pot.y), (s.x - pot.x, s.y - pot.y))
        return True

    def _judge(self, pot: MissionPot, visit: PotVisit, drift: Drift | None) -> None:
        visit.drift = drift.offset if drift is not None else (0.0, 0.0)
        visit.drift_known = drift is not None and drift.known
        off, turn = self.offset(pot, visit)
        visit.moved = off > self.config.moved_xy or turn > self.config.moved_yaw

    def rejudge(self, visits: dict[str, PotVisit]) -> list[MissionPot]:
        """At the patrol's end: the pots found moved with no recent neighbours to read the drift
        off (the first pots of a patrol or after SLAM's solve, or past a bay's divider), judged
        again on the neighbours read nearest in time to them since the same solve, those
        read after included (the pot itself left out); the pots no longer moved. Only a
        provisional ``moved`` is taken back, never one added: the drift grows with the patrol,
        so a neighbour located an hour later may carry drift this pot's early read never had."""
        changed = []
        for pot in self.mission.pots:
            visit = visits.get(pot.id)
            if visit is None or visit.located is None or visit.drift_known or not visit.moved:
                continue
            drift = self.drift.consensus(pot.x, pot.y, again=True)
            if drift is None:
                continue
            was = visit.moved
            self._judge(pot, visit, drift)
            if visit.moved != was:
                changed.append(pot)
        return changed

    def offset(self, pot: MissionPot, visit: PotVisit) -> tuple[float, float]:
        """How far (m) and how much turned (rad) the located pot is from the mission's, in the
        mission's frame (the map's drift there taken out)."""
        x, y, facing = in_mission_frame(visit)
        return math.hypot(x - pot.x, y - pot.y), abs(math.remainder(facing - pot.facing, 2 * math.pi))

    def where(self, pot: MissionPot, visit: PotVisit) -> tuple[float, float, float]:
        """Where the pot is believed to stand (x, y, facing; map frame): where the tag put a moved
        pot, else the mission's place carried by the map's drift there."""
        if visit.moved:
            return visit.located
        dx, dy = self.drift.near(pot.x, pot.y)
        return pot.x + dx, pot.y + dy, pot.facing

    def approach(self, pot: MissionPot, visit: PotVisit) -> Pose2D:
        """The approach pose to the pot where it is believed to stand (``where``): so a pot off
        by the map's drift alone is stood at right the first time."""
        return approach_pose(*self.where(pot, visit), self.mission.standoff)

    def search_looks(self, pot: MissionPot) -> list[Pose2D]:
        """Where to look for a pot whose tag was not at its approach pose: first a step back
        (a pot moved towards the robot puts its plate too close to frame, ``SEARCH_BACK``), then
        every pot of the map within ``search_radius`` of the mission's position from each side
        the robot fits, at the approach distance and a little farther: the looks the way the
        mission's plate faced first (a pot pushed about mostly still faces its aisle), nearest
        first within each."""
        here, grid = self.nav.map_pose(), self.nav.global_costmap.grid
        back = compose(here, Pose2D(-SEARCH_BACK, 0.0, 0.0))
        first = [back] if int(grid.cost_at(back.x, back.y)) < INSCRIBED else []
        occupancy = getattr(self.nav.localisation, "occupancy", None)
        if occupancy is None:
            return first
        blobs = pot_blobs(occupancy, self.config.pot_radius)
        near = blobs[np.hypot(blobs[:, 0] - pot.x, blobs[:, 1] - pot.y) <= self.config.search_radius] if len(blobs) else blobs
        out = [Pose2D(v.x, v.y, v.yaw) for standoff in (self.mission.standoff, self.mission.standoff + SEARCH_BACK)
               for v in looks(near, grid, standoff, SLANTS)]

        def order(p: Pose2D) -> tuple[bool, float]:
            facing_it = abs(math.remainder(p.yaw - (pot.facing + math.pi), 2 * math.pi)) < math.pi / 4
            return not facing_it, math.hypot(p.x - here.x, p.y - here.y)

        return first + sorted(out, key=order)
