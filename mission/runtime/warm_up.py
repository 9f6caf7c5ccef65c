"""The runtime's compiled kernels, compiled before its loop starts.

numba compiles a kernel on its first call and keeps the machine code in the package's
``__pycache__`` (``cache=True``), so every start after the first loads it in milliseconds. The
first start after an install or an upgrade compiles them all, and it did so inside the control
loop: the first people tick alone (the scan's returns, the scene lookup, segments, fits, bodies,
legs, the tracker) took 117 s with an empty cache on this 2-core machine under load (its median
tick: 0.8 ms), and the MPPI and costmap kernels followed on the first drive. The warm-up itself
takes 40 s with an empty cache (quiet) and 1.7 s with a warm one. On the robot that is a
loop standing still for minutes, the wheels cut by their watchdog and the link silent, the first
time a grower starts it.

So the hardware runtime calls ``warm_up`` once its devices are open (a missing one is said at
once) and before it schedules anything: the kernels the loop calls
(the people tick, the costmaps, the planner, MPPI and the collision monitor's outline; SLAM's
worker has its own, ``nav.slam.worker.warm_up``) run once on a synthetic scan of a small walled
room with a person in it, through the same code and so with the same argument types as on the
robot. ``tests/mission/test_warm_up.py`` runs a patrol with walkers after it and finds no kernel
compiled anew.
"""
from __future__ import annotations

import logging
import math
import time

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.robot_outline import Outline
from mission.runtime.config import LupinConfig
from mission.runtime.people import People
from nav.costmap.layered import global_costmap, local_costmap
from nav.mppi.controller import MppiController
from nav.occupancy import FREE, OCCUPIED, OccupancyMap
from nav.planner import NavfnPlanner

log = logging.getLogger(__name__)

ROOM = 2.0
"""The synthetic room's half-width, m: walls inside the lidar's range and the local costmap."""
LEGS = ((1.0, 0.11), (1.0, -0.11))
"""A person's legs ahead of the lidar (x, y), 0.07 m in radius, walking on +x."""
POT = (-1.0, 0.8)
RAYS = 500
SCANS = 6
SLOW = 2.0
"""A warm-up longer than this, s, compiled (rather than loaded): said at INFO."""


def warm_up(config: LupinConfig) -> float:
    """Run every kernel of the runtime's loop once; the seconds it took."""
    t0 = time.perf_counter()
    scans = [_scan(0.1 * k, 0.03 * k) for k in range(1, SCANS + 1)]
    _people(config, scans)
    _navigation(config, scans[-1])
    Outline(*config.hw.collision_monitor.chassis).inside(np.zeros(2), np.zeros(2), config.hw.collision_monitor.self_margin)
    took = time.perf_counter() - t0
    if took > SLOW:
        log.info("compiled the runtime's kernels in %.1f s (the first start since an install: cached from now on)", took)
    return took


def _scan(stamp: float, walked: float) -> LidarScan:
    """The lidar at the room's centre: the walls, the pot and the person ``walked`` m on."""
    a = np.arange(RAYS) * (2 * math.pi / RAYS) - math.pi
    c, s = np.cos(a), np.sin(a)
    r = ROOM / np.maximum(np.abs(c), np.abs(s))
    for (x, y), radius in [((lx + walked, ly), 0.07) for lx, ly in LEGS] + [(POT, 0.1)]:
        along = x * c + y * s
        off2 = x * x + y * y - along ** 2
        hit = (off2 <= radius ** 2) & (along > 0)
        r = np.where(hit, np.minimum(r, along - np.sqrt(np.maximum(radius ** 2 - off2, 0.0))), r)
    return LidarScan(stamp, a.astype(np.float32), r.astype(np.float32))


def _room(resolution: float = 0.05) -> OccupancyMap:
    n = int(round(2 * (ROOM + 0.2) / resolution))
    occ = np.full((n, n), FREE, np.int8)
    wall = int(round(0.2 / resolution))
    occ[wall, wall:-wall] = occ[-wall - 1, wall:-wall] = OCCUPIED
    occ[wall:-wall, wall] = occ[wall:-wall, -wall - 1] = OCCUPIED
    return OccupancyMap(occ, resolution, -(ROOM + 0.2), -(ROOM + 0.2))


def _people(config: LupinConfig, scans: list[LidarScan]) -> None:
    shown = [scans[0]]
    room = _room()
    people = People(config.perception.people, lambda: shown[0], Pose2D, Pose2D(), Pose2D, lambda: room,
                    lambda: Outline(*config.hw.collision_monitor.chassis), config.hw.collision_monitor.self_margin)
    people.watch([POT], config.patrol.pot_radius)
    for scan in scans:
        shown[0] = scan
        people.tick(scan.stamp)


def _navigation(config: LupinConfig, scan: LidarScan) -> None:
    cfg = config.nav
    local, whole = local_costmap(cfg.costmap), global_costmap(cfg.costmap)
    for costmap in (local, whole):
        costmap.update(scan, (0.0, 0.0, 0.0), (0.0, 0.0))
    start, goal = (-1.3, -0.8, 0.0), (1.3, -0.8, 0.0)  # along the room's south side, clear of the person
    NavfnPlanner(cfg.planner).plan(local.grid, start[:2], goal[:2])
    # a path 1 cm a point, so that the first trajectories reach the 20 points out path align
    # scores from; far from the goal, turned from the path (path angle), beside the goal (goal angle)
    xs = np.linspace(start[0], goal[0], 261)
    path = np.column_stack([xs, np.full_like(xs, start[1]), np.zeros_like(xs)])
    controller = MppiController(cfg.mppi, cfg.costmap)
    for pose, speed in ((start, 0.5), ((-1.3, -0.8, 1.2), 0.2), ((1.1, -0.8, 0.5), 0.1)):
        controller.compute(pose, (speed, 0.0, 0.0), path, goal, local.grid)
