"""The runtime's people: the person tracker at the scan rate, its tracks handed on as data.

``attach_people`` (called by ``attach_navigation``) builds :class:`People` and puts the people
guard (``hw.people_guard``) on the base above the collision monitor; navigation's person layers
and the report's ``people`` list (``mission.patrol.person_encounters``) read
``People.confident``, a ``hw.people.PeopleSource``. Every consumer gets the same tracks in ``odom``; none imports
perception.

The tracker needs to know what the greenhouse itself explains, so that a pot is not a person:
the map as it stood when the patrol started plus the pots the mission lists
(``perception.people.explained.StaticScene``: not the live SLAM map as it is, which writes in a
worker who stands still). So the tracker runs once the patrol says which pots it knows
(``watch``), with the map of the first tick that has one (SLAM's first map from the dock, or the
saved one AMCL localises on). A patrol mapping from the dock has seen little of its walls then,
and every wall it meets later, broken into short arcs by the pots in front and grazing angles,
would be a person: the default patrol took 244 s of robot time instead of 123, slowed and held
by walls. So the scene also takes in, each time SLAM hands a new map, its *structure*: the
occupied components longer than any person (``max_extent``, the tracker's own bound, bounding-box
diagonal, after closing 0.1 m gaps), which are walls and benches; a worker standing still, a
crouching one or a crate stays a small blob and is never taken in.

The rules act on tracks that have walked (``confident``: moved ``WALKED`` from where they were
first seen), from then on for as long as the track lives, standing or not. A standing thing is
not shown to be a person by its shape: a 0.3 m box seen corner-on is
two leg-shaped faces (0.9, like a pair of legs) and a moved pot one leg (0.6), and with the
rules on every unexplained track the box-in-aisle and moved-pot scenarios failed their pots (a
keep-out round something the robot must stand 0.35 m or 0.18 m from). Nor by the tracker's
speed alone: a box's seen centre shifts by up to half its width as the robot drives past it,
which the filter reads as a few tenths of a m/s (the box was "walking" in box-in-aisle); a body
that moved half a metre has walked. Someone who has stood
still since before the robot saw them is an obstacle with today's distances until they move,
the collision monitor's stop zone as ever.

========  ======  =======================================================
task      rate    why
========  ======  =======================================================
people    10 Hz   the lidar's rate: one tracker update per revolution
========  ======  =======================================================
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Optional, Sequence

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import Person
from hw.people_guard import PeopleGuard
from nav.frames import compose, transform_points
from nav.grid_geometry import GridGeometry, paste
from nav.occupancy import OccupancyMap
from nav.structure import long_components
from perception.people.config import PeopleConfig
from perception.people.explained import StaticScene
from perception.people.tracker import PersonTracker, odom_points

if TYPE_CHECKING:
    from mission.runtime.robot import Robot

HOP = 0.3
"""A track that moved more than this between two scans (3 m/s at 10 Hz, twice a brisk walk)
jumped to another thing rather than walked: its walk starts again from there, m."""

WALKED = 0.5
"""A track this far from where it was first seen has walked, m: more than a box's or a pot's
seen centre shifts with the view (half a 0.6 m crouching body, a 0.3 m box corner-on)."""

RATE = 10.0
"""Tracker updates per second: the C1's revolutions (a new scan each)."""


class People:
    def __init__(self, config: PeopleConfig, scan: Callable[[], Optional[LidarScan]], odom_pose: Callable[[], Pose2D],
                 lidar_mount: Pose2D, map_to_odom: Callable[[], Pose2D],
                 occupancy: Callable[[], Optional[OccupancyMap]]):
        self.config = config
        self.tracker = PersonTracker(config)
        self.scan, self.odom_pose, self.mount = scan, odom_pose, lidar_mount
        self.map_to_odom, self.occupancy = map_to_odom, occupancy
        self.tracks: tuple[Person, ...] = ()
        """The newest people, odom frame."""
        self.walked: set[int] = set()
        """Ids of the tracks that have walked: people (``confident``)."""
        self._origin: dict[int, tuple[float, float]] = {}
        self._last: dict[int, tuple[float, float]] = {}
        self.guard: PeopleGuard | None = None
        """The people guard on the base (``attach_people``)."""
        self.scene: StaticScene | None = None
        """What the greenhouse explains, frozen at the first map once the pots are known."""
        self._pots: np.ndarray | None = None
        self._pot_radius = 0.0
        self._stamp: float | None = None
        self._first: OccupancyMap | None = None
        self._live: OccupancyMap | None = None

    def current(self) -> Sequence[Person]:
        """The ``hw.people.PeopleSource`` every consumer holds."""
        return self.tracks

    def watch(self, pots_xy: Sequence[tuple[float, float]], pot_radius: float) -> Callable[[], Sequence[Person]]:
        """Start tracking with the mission's pots (map frame) as known; the scene is frozen at
        the next tick with a map. Returns the source of the people the rules act on (the
        tracks that have walked), for the report."""
        self._pots = np.asarray(pots_xy, dtype=float).reshape(-1, 2)
        self._pot_radius = pot_radius
        self.scene, self._first, self._live = None, None, None
        return self.confident

    def confident(self) -> Sequence[Person]:
        """The people the distance rules act on: the tracks that have walked (module docstring)."""
        return tuple(p for p in self.tracks if p.id in self.walked)

    def tick(self, now: float) -> None:
        if self._pots is None:
            return
        live = self.occupancy()
        if live is not self._live and live is not None:
            self._first = self._first or live
            self._live = live
            cells = Cells(live.geometry, first_and_structure(self._first, live, self.config.max_extent))
            self.scene = StaticScene(cells, self._pots, self._pot_radius, self.config.margin)
        if self.scene is None:
            return  # no map yet: a pot unexplained would be a person
        scan = self.scan()
        if scan is None or scan.stamp == self._stamp:
            return
        self._stamp = scan.stamp
        odom = self.odom_pose()
        lidar = compose(odom, self.mount)
        points = odom_points(scan.angles, scan.ranges, (lidar.x, lidar.y, lidar.yaw))
        explained = self.scene.explained(transform_points(self.map_to_odom(), points))
        self.tracks = self.tracker.update(scan.stamp, points, (odom.x, odom.y, odom.yaw), explained)
        last = self._last
        self._last = {p.id: (p.x, p.y) for p in self.tracks}
        # a track that jumped (its detection hopped to another thing: the next unknown pot of a
        # row, the far end of a wall) starts its walk again from where it landed
        self._origin = {p.id: (p.x, p.y) if p.id not in self._origin or p.id not in last
                        or np.hypot(p.x - last[p.id][0], p.y - last[p.id][1]) > HOP
                        else self._origin[p.id] for p in self.tracks}
        self.walked = {p.id for p in self.tracks if p.id in self.walked
                       or np.hypot(p.x - self._origin[p.id][0], p.y - self._origin[p.id][1]) > WALKED}


class Cells:
    """An occupied mask where ``StaticScene`` wants a map (its ``occupied()`` and ``geometry``)."""

    def __init__(self, geometry: GridGeometry, mask: np.ndarray):
        self.geometry, self._mask = geometry, mask

    def occupied(self) -> np.ndarray:
        return self._mask


def first_and_structure(first: OccupancyMap, live: OccupancyMap, max_extent: float, gap: float = 0.1) -> np.ndarray:
    """On ``live``'s grid: the first map's occupied cells, and ``live``'s structure (``nav.structure``:
    components whose bounding box's diagonal exceeds ``max_extent`` once gaps up to ``gap`` are closed)."""
    return long_components(live, max_extent, gap) | paste(first.occupied(), first.geometry, live.geometry, False)


def attach_people(robot: "Robot", map_to_odom: Callable[[], Pose2D],
                  occupancy: Callable[[], Optional[OccupancyMap]]) -> People:
    """The tracker on ``robot``'s lidar and odometry, scheduled; the people guard put on the base
    above whatever guards it now (the collision monitor), reading the same people."""
    cfg = robot.config
    base = robot.base
    people = People(cfg.perception.people, robot.hal.lidar.latest_scan, lambda: base.odometry.pose,
                    Pose2D(*cfg.nav.navigator.lidar_mount), map_to_odom, occupancy)
    people.guard = base.guard = PeopleGuard(cfg.hw.people_guard, lambda: base.odometry.pose,
                                            cfg.nav.costmap.robot_radius, people.confident, below=base.guard)
    robot.people = people
    robot.scheduler.every("people", RATE, people.tick)
    return people
