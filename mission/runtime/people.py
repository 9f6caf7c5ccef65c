"""The runtime's people: the person tracker at the scan rate, its tracks handed on as data.

``attach_people`` (called by ``attach_navigation``) builds :class:`People` and puts the people
guard (``hw.people_guard``) on the base above the collision monitor; navigation's person layers
and the report's ``people`` list (``mission.patrol.person_encounters``) read
``People.confident``, a ``hw.people.PeopleSource``. Every consumer gets the same tracks in ``odom``; none imports
perception.

The tracker needs to know what the greenhouse itself explains, so that a pot is not a person
(``mission.runtime.greenhouse``: the first map, the structure SLAM finds since, the known pots);
so it runs once the patrol says which pots it knows (``watch``). Whatever is tracked is cut out
of the map the structure is read from (a person shown as wide as their track ever was, and where
one was lost for ``LOST_KEEP``), so a grower paused against a wall is not taken in with it; and a
worker who already stood on their spot when the first map was made is found by their legs where
only that map explains returns (``mission.runtime.stood_at_start``).

The rules act on tracks shown to be people, from then on for as long as the track lives,
standing or not: tracks that have walked (moved ``WALKED`` from where they were first seen) and
tracks that showed legs (``perception.people.legs``: a pair of legs on ``LEGS_SEEN`` scans, or a
leg arc on most of the last ``LEG_WINDOW``, someone standing side-on). Not every unexplained
track: a 0.3 m box seen corner-on is two leg-wide faces and a moved pot one leg-wide sliver, and
with the rules on every unexplained track the box-in-aisle and moved-pot scenarios failed their
pots (a keep-out round something the robot must stand 0.35 m or 0.18 m from); the box's faces
meet at a corner with no gap and the pot's arc is wider than a leg, which the shape pass tells.
Nor by the tracker's speed alone: a box's seen centre shifts by up to half its width as the robot
drives past it, which the filter reads as a few tenths of a m/s; a body that moved half a metre
has walked. A crouching worker who has not moved since the robot saw them is one low block to
the lidar, the same as a crate: an obstacle with today's distances until they move, the collision
monitor's stop zone as ever.

========  ======  =======================================================
task      rate    why
========  ======  =======================================================
people    10 Hz   the lidar's rate: one tracker update per revolution
========  ======  =======================================================
"""
from __future__ import annotations

import logging
import math
from collections import deque
from dataclasses import replace
from typing import TYPE_CHECKING, Callable, Optional, Sequence

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import Person
from hw.people_guard import PeopleGuard
from hw.robot_outline import Outline
from mission.runtime.greenhouse import Greenhouse
from mission.runtime.stood_at_start import StoodAtStart, first_only, pairs_on
from nav.frames import compose, inverse
from nav.occupancy import OccupancyMap
from nav.walks import STRIDING
from perception.people.config import PeopleConfig
from perception.people.explained import StaticScene
from perception.people.legs import LegShapes, find as find_legs
from perception.people.returns import returns
from perception.people.tracker import PersonTracker

if TYPE_CHECKING:
    from mission.runtime.robot import Robot

log = logging.getLogger("lupin")

HOP = 0.3
"""A track that moved more than this between two scans (3 m/s at 10 Hz, twice a brisk walk)
jumped to another thing rather than walked: its walk starts again from there, m."""

WALKED = 0.5
"""A track this far from where it was first seen has walked, m: more than a box's or a pot's
seen centre shifts with the view (half a 0.6 m crouching body, a 0.3 m box corner-on)."""

LEGS_SEEN = 3
"""A track seen as a pair of legs (``perception.people.legs``) on this many scans is someone
standing: one scan's pair can be a fluke of noise on two slivers, three are not."""

LEG_WINDOW, LEG_SCANS = 10, 7
"""A track seen as a leg arc on at least ``LEG_SCANS`` of its last ``LEG_WINDOW`` scans is
someone standing side-on (one leg hides the other: a worker facing along the aisle the robot
drives, people-aisle-worker). A pot, the one other round thing in a greenhouse, fits the leg
window on under a tenth of its scans (``PeopleConfig.leg_radius``): a moved pot is not a
person, a post or a pipe might be, the safe side."""

LEGS_NEAR = 0.3
"""A pair of legs or a leg arc belongs to the track whose centre lies within this of it, m:
the track's centre is put a leg's radius behind what was seen."""

LOST_KEEP = 10.0
"""Where a person's track was lost is still cut out of the map the structure is read from
(``without``) this long, s, as wide as the track ever was: a cart pusher pauses at the end of
their aisle for seconds (spec/world.md ``pause``), and a track reborn there within ``REMEMBER``
is them again. Cut only while tracked, by the track's radius of the moment, a cart paused against
a wall shrank scan by scan as the map took its far side in with the wall, until the whole of it
was the wall's (safety.people held-out seed 107, 1,272-1,281 s: the track's radius fell from
0.5 m to 0.17 m, it died, and the robot drove into the cart still standing there). Not wider
than the track ever was: cut 0.7 m round every person shown, wall cells SLAM once saw free went
with it, the walls' broken pieces were people, and their tracks cut more (the same seed: the
patrol ended stuck among ghosts)."""
REMEMBER = 3.0
"""Where a person's track was lost is remembered this long, s: a leg hidden behind the other, a
worker cut by the map where they touch a wall, or out of view behind a pot for a few steps."""

REBORN = 0.8
"""A track this near where a person's was lost, and not shown a person itself, is theirs, m: the
gate of the tracker (``PeopleConfig.gate``), a step and a half."""

FAULT_LOG_GAP = 60.0
"""A failing tracker is logged at most this often, s (with its traceback)."""

ROBOT_REACH = 0.45
"""A track this near another robot's centre is that robot, m: its 0.22 m radius, its arm out
front (the wrist camera ~0.3 m ahead), and what its pose told over the link lags behind."""
RATE = 10.0
"""Tracker updates per second: the C1's revolutions (a new scan each)."""


class People:
    def __init__(self, config: PeopleConfig, scan: Callable[[], Optional[LidarScan]], odom_pose: Callable[[], Pose2D],
                 lidar_mount: Pose2D, map_to_odom: Callable[[], Pose2D],
                 occupancy: Callable[[], Optional[OccupancyMap]], body: Callable[[], Outline], body_margin: float):
        """``body``: the robot's outline as it stands now (the chassis and the arm, base frame:
        the collision monitor's), ``body_margin`` round it, m: the returns within it are the
        robot's own and dropped before the tracker sees them (``perception.people.returns``)."""
        self.config = config
        self.tracker = PersonTracker(config)
        self.scan, self.odom_pose, self.mount = scan, odom_pose, lidar_mount
        self.body, self.body_margin = body, body_margin
        self.map_to_odom, self.occupancy = map_to_odom, occupancy
        self.tracks: tuple[Person, ...] = ()
        """The newest people, odom frame."""
        self._shown: tuple[Person, ...] = ()
        self.walked: set[int] = set()
        """Ids of the tracks that have walked: people (``confident``)."""
        self.pairs: dict[int, int] = {}
        """Per track: on how many scans it was seen as a pair of legs."""
        self.inherited: set[int] = set()
        """Ids of the tracks found where a person's track was just lost (``_carry``)."""
        self._gone: list[tuple[float, float, float, int | None]] = []
        """Where a person's track was lost: x, y, when, their id (None: their track went on
        elsewhere, ``_carry``)."""
        self._lost: list[tuple[float, float, float, float]] = []
        """Where a person's track was lost (x, y, widest radius, when; odom): cut from the
        structure (``LOST_KEEP``)."""
        self._widest: dict[int, float] = {}
        """Per person shown: the widest their track has been, m."""
        self._stood: dict[int, tuple[float, float, float]] = {}
        """Per person shown: where their track last stood still (slower than ``STRIDING``: a
        paused cart's track reads up to ~0.3 m/s of jitter), and when."""
        self._alias: dict[int, int] = {}
        """Tracker id -> the id it goes by: a lost person's, for the track born where they were lost."""
        self._raw: dict[int, int] = {}
        """Last scan's tracks: the id each went by -> its tracker id."""
        self.robots: Callable[[], Sequence] = tuple
        """Where the fleet's other robots say they stand, map frame (``mission.link.peers``): a
        track on one is that robot (its lidar puck and arm in the scan plane look like a leg
        pair), never a person: measured on ``fleet.patrol_small``, robots stepped "out of a
        walker's way" of each other in a greenhouse with no one in it."""
        self.arcs: dict[int, deque[bool]] = {}
        """Per track: whether it was seen as a leg arc, on each of its last ``LEG_WINDOW`` scans."""
        self._origin: dict[int, tuple[float, float]] = {}
        self._last: dict[int, tuple[float, float]] = {}
        self.failures = 0
        """Scans the tracker failed on (``tick``)."""
        self._failed_at = -math.inf
        self.guard: PeopleGuard | None = None
        """The people guard on the base (``attach_people``)."""
        self.greenhouse: Greenhouse | None = None
        """What the greenhouse explains (``watch`` on)."""
        self.stood = StoodAtStart()
        self._stamp: float | None = None

    def current(self) -> Sequence[Person]:
        """The ``hw.people.PeopleSource`` every consumer holds."""
        return self.tracks

    def watch(self, pots_xy: Sequence[tuple[float, float]], pot_radius: float) -> Callable[[], Sequence[Person]]:
        """Start tracking with the mission's pots (map frame) as known; the scene is frozen at
        the next tick with a map. Returns the source of the people the rules act on (the
        tracks that have walked), for the report."""
        self.greenhouse = Greenhouse(self.config, pots_xy, pot_radius)
        self.stood = StoodAtStart()
        return self.confident

    @property
    def pots(self) -> np.ndarray:
        """(N, 2) the pots the tracker knows for pots, map frame (none before ``watch``)."""
        return np.empty((0, 2)) if self.greenhouse is None else self.greenhouse.pots

    @property
    def scene(self) -> StaticScene | None:
        """What the greenhouse explains now (None before a map)."""
        return None if self.greenhouse is None else self.greenhouse.scene

    def confident(self) -> Sequence[Person]:
        """The people the distance rules act on (module docstring): chosen once a scan, read by
        the guard at every base tick and by both costmaps and the navigator."""
        return self._shown

    def legged(self, track: int) -> bool:
        """Has the track shown a person's legs (a pair, or a leg arc scan after scan)?"""
        return self.pairs.get(track, 0) >= LEGS_SEEN or sum(self.arcs.get(track, ())) >= LEG_SCANS

    def tick(self, now: float) -> None:
        """One tracker update on the newest scan. A fault in it (a numerical corner the fits did
        not foresee) is logged and this scan's people dropped, never raised: it would take the
        whole runtime down with it, base and e-stop included, while the collision monitor below
        the people guard goes on judging the raw scan either way."""
        try:
            self._tick()
        except Exception:  # noqa: BLE001 - the runtime's control loop must outlive the tracker
            self.failures += 1
            if now - self._failed_at >= FAULT_LOG_GAP:
                log.exception("person tracker failed on a scan (%d so far); people dropped for it", self.failures)
                self._failed_at = now
            self.tracks, self._shown = (), ()

    def _tick(self) -> None:
        house = self.greenhouse
        if house is None:
            return
        house.see(self.occupancy(), self._tracked_in_map)
        if house.scene is None:
            return  # no map yet: a pot unexplained would be a person
        scan = self.scan()
        if scan is None or scan.stamp == self._stamp:
            return
        self._stamp = scan.stamp
        odom, m2o = self.odom_pose(), self.map_to_odom()
        lidar = compose(odom, self.mount)
        points, in_map = returns(scan.angles, scan.ranges, (lidar.x, lidar.y, lidar.yaw), (odom.x, odom.y, odom.yaw),
                                 self.body(), self.body_margin, (m2o.x, m2o.y, m2o.yaw))
        explained, bare = house.scene.explained(in_map), house.bare.explained(in_map)
        lidar_xy = np.array([lidar.x, lidar.y])
        first = first_only(points, lidar_xy, explained, bare)
        # one shape pass a scan, on what the structure and the pots leave: the tracks' legs and
        # the legs of someone the first map holds (``stood_at_start``)
        shapes = find_legs(points, lidar_xy, bare, self.config) if len(first) or self.tracks else None
        if len(first) and self._stood_at_start(scan.stamp, shapes.pairs, first, m2o):
            explained = house.scene.explained(in_map)
        shown = {p.id: (p.x, p.y) for p in self.confident()}
        raw = self.tracker.update(scan.stamp, points, (odom.x, odom.y, odom.yaw), explained)
        self.tracks = self._carry(scan.stamp, raw, shown)
        if self.tracks:
            self._count_legs(shapes if shapes is not None else find_legs(points, lidar_xy, bare, self.config))
        else:
            self.pairs, self.arcs = {}, {}
        last = self._last
        self._last = {p.id: (p.x, p.y) for p in self.tracks}
        # a track that jumped (its detection hopped to another thing: the next unknown pot of a
        # row, the far end of a wall) starts its walk again from where it landed
        self._origin = {p.id: (p.x, p.y) if p.id not in self._origin or p.id not in last
                        or math.hypot(p.x - last[p.id][0], p.y - last[p.id][1]) > HOP
                        else self._origin[p.id] for p in self.tracks}
        self.walked = {p.id for p in self.tracks if p.id in self.walked
                       or math.hypot(p.x - self._origin[p.id][0], p.y - self._origin[p.id][1]) > WALKED}
        robots = self._robots_in_odom()
        self._shown = tuple(p for p in self.tracks
                            if not any(math.hypot(x - p.x, y - p.y) <= ROBOT_REACH for x, y in robots)
                            and (p.id in self.walked or p.id in self.inherited or self.legged(p.id)))
        self._widest = {p.id: max(p.radius, self._widest.get(p.id, 0.0)) for p in self._shown}

    def _stood_at_start(self, stamp: float, pairs: np.ndarray, first: np.ndarray, m2o: Pose2D) -> bool:
        """Someone standing where only the first map explains returns (``stood_at_start``):
        True when found, their cells no longer explaining and the scene refrozen."""
        spots = self.stood.found(stamp, pairs_on(pairs, first, m2o))
        if not spots:
            return False
        self.greenhouse.clear(spots)
        log.info("someone standing since the first map at %s: a person, not the greenhouse",
                 ", ".join(f"({x:.1f}, {y:.1f})" for x, y in spots))
        return True

    def _tracked_in_map(self) -> list[tuple[float, float, float]]:
        """Every track now, shown a person or not yet: (x, y, radius), map frame. Not only the
        people shown: a grower with a cart who had stopped for the robot 0.15 m from a wall was
        a track not yet shown again, and the next map took them in with the wall (safety.people
        seed 2, 290 s: the robot went on to 0.13 m of the cart). A person shown is cut as wide as
        their track ever was, and where one was lost too, for ``LOST_KEEP``."""
        m2o, now = self.map_to_odom(), self._stamp or 0.0
        self._lost = [s for s in self._lost if now - s[3] <= LOST_KEEP]
        spots = [(p.x, p.y, self._widest.get(p.id, p.radius)) for p in self.tracks]
        spots += [(x, y, r) for x, y, r, _ in self._lost]
        return [(q.x, q.y, r) for x, y, r in spots for q in [compose(m2o, Pose2D(x, y, 0.0))]]

    def _robots_in_odom(self) -> list[tuple[float, float]]:
        """Where the fleet's other robots say they are, odom frame (a track within
        ``ROBOT_REACH`` of one is that robot). ``map_to_odom`` takes odom points into the map,
        so its inverse takes the told poses back: composed the wrong way round, a robot 0.19 m
        of SLAM correction from its odometry placed the others 0.4 m off, and a robot passing
        another's dock was a person "at the goal" (``fleet.patrol_small``)."""
        robots = self.robots()
        if not robots:
            return []
        o2m = inverse(self.map_to_odom())
        return [(q.x, q.y) for q in (compose(o2m, r) for r in robots)]

    def _carry(self, stamp: float, raw: Sequence[Person], shown: dict[int, tuple[float, float]]) -> tuple[Person, ...]:
        """``raw`` under the ids they go by. A person's track lost (hidden a moment, or cut by the
        map at a wall) leaves where it was for ``REMEMBER`` seconds; a track born within
        ``REBORN`` of that is them again (``inherited``): a person at once, not after another half
        metre of walking (people-crossing-no-yield: the grower pausing by the wall at the end of
        each crossing came back as a new track each time, and the robot drove up to them while it
        had still to be shown), and under their id, so that what the navigator remembers of them
        goes on (``nav.people_nearby.walks``: safety.people seed 1, 2,555 s: a cart pusher who
        does not yield, paused at the end of their cross aisle, came back as a new track with no
        walk, so no lane; the robot stepped into it, and they walked back into the robot). Not
        only a track born there: any track not shown a person itself. A cart and its pusher seen
        as two bodies are two tracks, the cart's born beside the person's; the person's track
        hopped off onto the pusher's legs and died, and the cart, standing where the grower had
        stopped for the robot, was nobody (held-out seed 3, 244-249 s: the robot drove up to
        0.13 m of it and waited there 40 s while its grower waited for it).

        A person's track that leaves where it stood still (``_walked_off``) leaves that place
        the same way, their id going on with the track: a thing there not shown a person is
        one, under its own id. A cart pusher paused at the end of their aisle, and a grower
        walking past them drew the track off onto themselves (one blob as they passed); the
        cart stayed a track never shown a person, and the robot drove along it at 0.08 m
        (safety.people seed 1, 274-282 s)."""
        live = {p.id for p in raw}
        self._gone = [g for g in self._gone if stamp - g[2] <= REMEMBER]
        lost = [(x, y, stamp, k) for k, (x, y) in shown.items() if self._raw.get(k) not in live]
        self._gone += lost
        self._lost += [(x, y, self._widest.get(k, 0.0), stamp) for x, y, _, k in lost]
        carried = set()
        for p in raw:
            if self._alias.get(p.id, p.id) in shown or not self._gone:
                continue
            d = [math.hypot(p.x - x, p.y - y) for x, y, _, _ in self._gone]
            k = d.index(min(d))
            if d[k] <= REBORN:
                whose = self._gone.pop(k)[3]
                if whose is not None:
                    self._alias[p.id] = whose
                carried.add(p.id if whose is None else whose)
        self._alias = {k: v for k, v in self._alias.items() if k in live}
        self._raw = {self._alias.get(k, k): k for k in live}
        tracks = tuple(replace(p, id=self._alias[p.id]) if p.id in self._alias else p for p in raw)
        self.inherited = ({p.id for p in tracks} & self.inherited) | carried
        self._walked_off(stamp, tracks, shown)
        return tracks

    def _walked_off(self, stamp: float, tracks: Sequence[Person],
                    shown: dict[int, tuple[float, float]]) -> None:
        """Remember where each person shown stands still; once their track is ``REBORN`` from
        there (they walked off, or were drawn off onto someone passing), the place is one a
        person was lost from (``_gone``, no id: theirs goes on with the track)."""
        stood = {}
        for p in tracks:
            if p.id not in shown:
                continue
            if math.hypot(p.vx, p.vy) < STRIDING:
                stood[p.id] = (p.x, p.y, stamp)
            elif p.id in self._stood:
                x, y, when = self._stood[p.id]
                if math.hypot(p.x - x, p.y - y) > REBORN:
                    self._gone.append((x, y, stamp, None))
                elif stamp - when <= REMEMBER:
                    stood[p.id] = (x, y, when)
        self._stood = stood

    def _count_legs(self, shapes: LegShapes) -> None:
        """Count, per track, the scans on which it was seen as a pair of legs or a leg arc (the
        scan's ``shapes``; the nearest track within ``LEGS_NEAR`` of each); tracks gone are
        forgotten."""
        ids = [p.id for p in self.tracks]
        self.pairs = {k: self.pairs.get(k, 0) for k in ids}
        self.arcs = {k: self.arcs[k] if k in self.arcs else deque(maxlen=LEG_WINDOW) for k in ids}
        at = np.array([(p.x, p.y) for p in self.tracks])
        for k in self._nearest(at, shapes.pairs):
            self.pairs[ids[k]] += 1
        arc = set(self._nearest(at, shapes.arcs))
        for k, track in enumerate(ids):
            self.arcs[track].append(k in arc)

    @staticmethod
    def _nearest(at: np.ndarray, found: np.ndarray) -> list[int]:
        """For each found shape, the index of the nearest track within ``LEGS_NEAR`` (if any)."""
        if not len(found):
            return []
        d = np.hypot(*(at[:, None, :] - found[None, :, :]).transpose(2, 0, 1))
        k = np.argmin(d, axis=0)
        return [int(i) for i, j in zip(k, range(len(found))) if d[i, j] <= LEGS_NEAR]


def attach_people(robot: "Robot", map_to_odom: Callable[[], Pose2D],
                  occupancy: Callable[[], Optional[OccupancyMap]]) -> People:
    """The tracker on ``robot``'s lidar and odometry, scheduled; the people guard put on the base
    above whatever guards it now (the collision monitor), reading the same people."""
    cfg = robot.config
    base = robot.base
    people = People(cfg.perception.people, robot.hal.lidar.latest_scan, lambda: base.odometry.pose,
                    Pose2D(*cfg.nav.navigator.lidar_mount), map_to_odom, occupancy,
                    lambda: robot.monitor.outline, cfg.hw.collision_monitor.self_margin)
    people.guard = base.guard = PeopleGuard(cfg.hw.people_guard, lambda: base.odometry.pose,
                                            cfg.nav.costmap.robot_radius, people.confident, below=base.guard,
                                            returns=lambda: robot.monitor.points)
    robot.people = people
    robot.scheduler.every("people", RATE, people.tick)
    return people
