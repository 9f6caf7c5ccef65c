"""The layered costmap: layers merged into one master grid, the local and global factories.

As Nav2's LayeredCostmap, each update runs the layers in order on a fresh master grid:

1. static (global only): the map's costs overwrite the master (Nav2's StaticLayer default);
2. obstacle: merged by maximum, except that a layer cell it has not observed (255) leaves the
   master alone and an observed one replaces an unknown master cell (Nav2's updateWithMax), so
   scans uncover unknown space but never erase the map's walls;
3. inflation: the halo around every lethal cell (``nav.costmap.inflation``);
4. people (both costmaps): tracked people's keep-out discs and falloff written over the
   inflated master (``nav.costmap.people``; after inflation, since a keep-out already counts the
   robot's radius). ``without_people`` is the same master with the people's bodies taken out
   instead: the navigator plans on it to tell "a person is in the only way" from "no way";
5. robots (both costmaps): the fleet's other robots' footprints, the same way (``nav.costmap.robots``;
   nothing for a robot alone). ``without_people`` leaves them out too: they move on like people.

``local_costmap`` is the seed's 3 x 3 m window in ``odom`` rolling with the robot: before each
update it re-centres on the robot by whole cells (the window's corners stay on the world's
0.05 m lattice, so its cells line up with the global map's), keeping the overlap; it starts free.
``global_costmap`` starts as a small unknown patch around the map origin and grows, never
shrinks: to take in the whole map whenever one arrives (as Nav2's static layer resizes the
master to its map), and to take in the robot and each goal before a plan (``cover``), so a
goal in unexplored ground is planned to through unknown space (allow_unknown) rather than
being "outside the costmap". Its memory follows the greenhouse, not a worst-case square. The master is
rebuilt in full every update: at 5 Hz on 60 x 60 cells and 1 Hz on 480 x 480 it costs less than
the bookkeeping Nav2 uses to avoid it (see ``lupin bench nav.local_costmap``).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import PeopleSource, nobody
from nav.costmap.config import CostmapsConfig, PersonLayerConfig
from nav.costmap.grid import FREE, UNKNOWN, CostGrid
from nav.costmap.inflation import InflationLayer
from nav.costmap.obstacle import ObstacleLayer
from nav.costmap.people import PersonLayer
from nav.costmap.robots import RobotsLayer
from nav.costmap.static import StaticLayer
from nav.frames import inverse
from nav.grid_geometry import GridGeometry, paste


GROW_STEP = 64
"""Cells the global costmap grows by on a side at a time (3.2 m at 0.05 m): it follows the map
every few metres of new ground, not every second."""
START_SIZE = 4.0
"""Side of the global costmap before any map or goal, m."""


class Costmap:
    def __init__(self, frame: CostGrid, obstacle: ObstacleLayer, inflation: InflationLayer,
                 static: StaticLayer | None = None, rolling: bool = False, people: PersonLayer | None = None,
                 robots: RobotsLayer | None = None):
        self._default = int(frame.data.flat[0])
        self.obstacle, self.inflation, self.static, self.people = obstacle, inflation, static, people
        self.robots = robots
        self.rolling = rolling
        self._grid = frame.copy()
        self._rebuild()

    @property
    def grid(self) -> CostGrid:
        """The master (inflated) grid. A new object after every change: hold it, it will not move."""
        return self._grid

    def update(self, scan: LidarScan, sensor_pose: tuple[float, float, float], robot_xy: tuple[float, float]) -> None:
        """Mark and clear from one scan; ``sensor_pose`` is the lidar in this map's frame."""
        if self.rolling:
            self._follow(robot_xy)
        self.obstacle.update(scan, sensor_pose)
        self._rebuild()

    def clear(self, static: bool = False) -> None:
        """Forget every observation (Nav2's clear_entirely_*_costmap); a static map stays unless
        ``static`` (the map reset: the map itself is being erased)."""
        self.obstacle.reset()
        if static and self.static is not None:
            self.static.costs = None
        self._rebuild()

    def set_static(self, occupancy: np.ndarray, resolution: float, origin_x: float, origin_y: float) -> None:
        """Feed the static layer a map_server occupancy grid (int8 [iy, ix], -1 unknown, 0..100);
        the costmap grows to take the whole map in."""
        if self.static is None:
            raise ValueError("this costmap has no static layer (the local costmap is obstacle + inflation only)")
        x0, x1, y0, y1 = GridGeometry.of(np.asarray(occupancy), resolution, origin_x, origin_y).extent
        self._grow(x0, y0, x1, y1)
        self.static.set_map(occupancy, resolution, origin_x, origin_y, self.obstacle.grid)
        self._rebuild()

    def cover(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """Grow, if need be, to take in the world box (the robot and a goal, with room round
        them); a rolling window only follows the robot."""
        if not self.rolling and self._grow(x0, y0, x1, y1):
            self._rebuild()

    # -- internals -----------------------------------------------------------------------------

    def _grow(self, x0: float, y0: float, x1: float, y1: float) -> bool:
        old = self.obstacle.grid.geometry
        new = old.grown_to_cover(x0, y0, x1, y1, GROW_STEP)
        if new is old:
            return False
        self.obstacle.resize(new)
        if self.static is not None and self.static.costs is not None:
            self.static.costs = paste(self.static.costs, old, new, self.static.unknown)
        return True

    def _follow(self, robot_xy: tuple[float, float]) -> None:
        g = self.obstacle.grid
        res = g.resolution
        want_x = math.floor((robot_xy[0] - g.width * res / 2) / res + 0.5)
        want_y = math.floor((robot_xy[1] - g.height * res / 2) / res + 0.5)
        dx, dy = want_x - round(g.origin_x / res), want_y - round(g.origin_y / res)
        if dx or dy:
            self.obstacle.shift(dx, dy)

    def without_people(self, margin: float = 0.1) -> CostGrid:
        """The grid as it would be with the people's bodies (their radius and ``margin``) free:
        what is left once they step aside. Rebuilt on demand (a failed plan), not kept."""
        master, geo = self._merged(), self.obstacle.grid.geometry
        if self.people is not None:
            cx, cy = geo.centre_of(np.arange(geo.width)[None, :], np.arange(geo.height)[:, None])
            for p in self.people.present():
                master[np.hypot(cx - p.x, cy - p.y) <= p.radius + margin] = FREE
        return CostGrid(self.inflation.apply(master), geo.resolution, geo.origin_x, geo.origin_y)

    def _merged(self) -> np.ndarray:
        """The static and obstacle layers merged, before inflation."""
        layer = self.obstacle.grid
        if self.static is not None and self.static.costs is not None:
            master = self.static.costs.copy()
        else:
            master = np.full(layer.data.shape, self._default, dtype=np.uint8)
        seen = layer.data != UNKNOWN
        take = seen & ((master == UNKNOWN) | (layer.data > master))
        master[take] = layer.data[take]
        return master

    def _rebuild(self) -> None:
        layer = self.obstacle.grid
        costs = self.inflation.apply(self._merged())
        if self.people is not None:
            costs = self.people.apply(costs, layer.geometry)
        if self.robots is not None:
            costs = self.robots.apply(costs, layer.geometry)
        self._grid = CostGrid(costs, layer.resolution, layer.origin_x, layer.origin_y)


def _inflation(cfg: CostmapsConfig) -> InflationLayer:
    return InflationLayer(cfg.resolution, cfg.robot_radius, cfg.inflation_radius, cfg.cost_scaling_factor)


def _people(cfg: CostmapsConfig, layer: PersonLayerConfig, people: PeopleSource,
            frame: Callable[[], Pose2D]) -> PersonLayer:
    return PersonLayer(layer, cfg.robot_radius, cfg.cost_scaling_factor, people, frame)


def _robots(cfg: CostmapsConfig, frame: Callable[[], Pose2D]) -> RobotsLayer:
    return RobotsLayer(cfg.robots, cfg.robot_radius, cfg.cost_scaling_factor, frame)


def _cells(metres: float, resolution: float) -> int:
    return max(1, int(round(metres / resolution)))


def local_costmap(cfg: CostmapsConfig, people: PeopleSource = nobody,
                  map_to_odom: Callable[[], Pose2D] = Pose2D) -> Costmap:
    """The 3 x 3 m window rolling with the robot (``odom``), obstacle + inflation + people
    (``people``: the tracker's, in odom) + robots (map frame, placed by the inverse of
    ``map_to_odom``), starts free (or unknown with ``track_unknown_space``); centred on the
    odom origin until the first update."""
    lc, res = cfg.local_costmap, cfg.resolution
    n = _cells(lc.size, res)
    default = UNKNOWN if lc.track_unknown_space else FREE
    corner = math.floor(-n / 2 + 0.5) * res
    frame = CostGrid.filled(n, n, res, corner, corner, default)
    obstacle = ObstacleLayer(frame.copy(), cfg.obstacle_min_range, lc.obstacle_max_range, lc.raytrace_max_range,
                             lc.inf_is_valid)
    return Costmap(frame, obstacle, _inflation(cfg), rolling=True,
                   people=_people(cfg, lc.people, people, Pose2D), robots=_robots(cfg, lambda: inverse(map_to_odom())))


def global_costmap(cfg: CostmapsConfig, people: PeopleSource = nobody,
                   odom_in_map: Callable[[], Pose2D] = Pose2D) -> Costmap:
    """The growing map in ``map``, static + obstacle + inflation + people (the tracker's, in
    odom, placed by ``odom_in_map``: the localisation's ``map -> odom``); starts as an unknown
    patch ``START_SIZE`` across round the map origin."""
    gc, res = cfg.global_costmap, cfg.resolution
    default = UNKNOWN if gc.track_unknown_space else FREE
    start = GridGeometry.covering(-START_SIZE / 2, -START_SIZE / 2, START_SIZE / 2, START_SIZE / 2, res)
    frame = CostGrid.filled(start.width, start.height, res, start.origin_x, start.origin_y, default)
    obstacle = ObstacleLayer(frame.copy(), cfg.obstacle_min_range, gc.obstacle_max_range, gc.raytrace_max_range,
                             gc.inf_is_valid)
    static = StaticLayer(gc.free_thresh, gc.occupied_thresh, gc.track_unknown_space)
    return Costmap(frame, obstacle, _inflation(cfg), static, people=_people(cfg, gc.people, people, odom_in_map),
                   robots=_robots(cfg, Pose2D))
