"""Costmap and planner benchmarks: NavFn across a 400 x 400 map and along a 100 x 30 m one, full
inflation of 400 x 400 and 2000 x 2000 maps, and one local-costmap update from a 500-point scan.

The maps are synthetic greenhouses at the seed's 0.05 m: walls round the floor and pots
(r 0.10 m) 1 m apart in rows 1 m apart, the built-in greenhouse's layout repeated. Each benchmark
also reports the alternative it was measured against, so the figures justify numba:
``edt_median_ms`` (inflation through OpenCV's exact distance transform), ``numpy_raytrace_ms``
versus ``numba_raytrace_ms`` (clearing the scan's beams), ``python_wavefront_ms`` (NavFn's
wavefront interpreted, one run).
"""
from __future__ import annotations

import time

import cv2
import numpy as np

from hw.interfaces import LidarScan
from lupin.bench import Sample, benchmark, time_ms
from mission.runtime.config import LupinConfig
from nav.costmap.grid import FREE, LETHAL, UNKNOWN, CostGrid
from nav.costmap.inflation import InflationLayer
from nav.costmap.layered import local_costmap
from nav.costmap.raytrace import clear_rays, ray_cells
from nav.planner import NavfnPlanner, propagate

RES = 0.05


def _greenhouse(cells: int, unknown_fraction: float = 0.0, height: int | None = None) -> np.ndarray:
    """Layer costs (0 free / 254 lethal / 255 unknown) of a greenhouse ``cells`` wide (and as
    high, unless ``height``)."""
    height = cells if height is None else height
    m = np.zeros((height, cells), np.uint8)
    m[[0, -1], :] = m[:, [0, -1]] = LETHAL
    step, radius = int(round(1.0 / RES)), int(round(0.10 / RES))
    for y in range(2 * step, height - step, step):
        for x in range(2 * step, cells - 2 * step, step):
            cv2.circle(m, (x, y), radius, LETHAL, -1)
    if unknown_fraction:
        m[: int(height * unknown_fraction), :] = np.where(m[: int(height * unknown_fraction), :] == LETHAL,
                                                          LETHAL, UNKNOWN)
    return m


def _inflation(config: LupinConfig) -> InflationLayer:
    c = config.nav.costmap
    return InflationLayer(c.resolution, c.robot_radius, c.inflation_radius, c.cost_scaling_factor)


def _inflate(config: LupinConfig, cells: int, n: int) -> Sample:
    layer, master = _inflation(config), _greenhouse(cells, unknown_fraction=0.3)
    times = time_ms(lambda: layer.apply(master), n)
    edt = time_ms(lambda: layer.apply_edt(master), max(3, n // 4))
    return Sample(times, {"cells": cells * cells, "lethal_cells": int((master == LETHAL).sum()),
                          "edt_median_ms": round(float(np.median(edt)), 3),
                          "same_result": bool(np.array_equal(layer.apply(master), layer.apply_edt(master)))})


@benchmark("nav.inflate_400")
def inflate_400(config: LupinConfig) -> Sample:
    """Full inflation of a 400 x 400 (20 x 20 m) greenhouse map, a third of it unknown."""
    return _inflate(config, 400, 50)


@benchmark("nav.inflate_2000")
def inflate_2000(config: LupinConfig) -> Sample:
    """Full inflation of a 2000 x 2000 (100 x 100 m) greenhouse map (Nav2: 48.9 ms single-threaded)."""
    return _inflate(config, 2000, 12)


@benchmark("nav.plan_400")
def plan_400(config: LupinConfig) -> Sample:
    """NavFn across an inflated 400 x 400 greenhouse, corner to far corner through the pot rows."""
    grid = CostGrid(_inflation(config).apply(_greenhouse(400)), RES, 0.0, 0.0)
    planner = NavfnPlanner(config.nav.planner)
    pairs = [((0.5, 0.5), (19.5, 19.5)), ((19.5, 0.5), (0.5, 19.5)), ((0.5, 10.5), (19.5, 9.5))]
    k = iter(range(10 ** 9))
    path_len = []

    def once():
        start, goal = pairs[next(k) % len(pairs)]
        path = planner.plan(grid, start, goal)
        path_len.append(len(path))

    times = time_ms(once, 30)
    cost = np.full((402, 402), 254, np.uint8)
    cost[1:-1, 1:-1] = np.where(grid.data >= 253, 254, 50 + (0.8 * grid.data).astype(np.uint8))
    t0 = time.perf_counter()
    pot = propagate.py_func(cost.ravel(), 402, 11 * 402 + 11, 391 * 402 + 391)  # inner (10, 10) to (390, 390)
    interpreted = (time.perf_counter() - t0) * 1000.0
    assert pot[391 * 402 + 391] < 1e10, "the interpreted wavefront did not reach the far corner"
    return Sample(times, {"cells": 400 * 400, "path_points_median": int(np.median(path_len)),
                          "python_wavefront_ms": round(interpreted, 1)})


@benchmark("nav.plan_long")
def plan_long(config: LupinConfig) -> Sample:
    """NavFn along a 100 x 30 m greenhouse at 0.05 m (2000 x 600 cells, 2,600 pots): the longest
    plans a patrol of a commercial greenhouse asks for (end to end, corner to corner) and a short
    one, each replanned as the navigator does at 1 Hz. Dijkstra's wavefront stops once the goal
    has a potential, so a short plan costs little whatever the map's size; the end-to-end plans are
    the worst case (goal 50 ms)."""
    grid = CostGrid(_inflation(config).apply(_greenhouse(2000, height=600)), RES, 0.0, 0.0)
    planner = NavfnPlanner(config.nav.planner)
    pairs = [((0.5, 0.5), (99.5, 29.5)), ((99.5, 0.5), (0.5, 29.5)), ((0.5, 15.5), (99.5, 14.5)),
             ((0.5, 0.5), (10.5, 0.5))]
    k = iter(range(10 ** 9))
    lengths = {}

    def once():
        start, goal = pairs[next(k) % len(pairs)]
        path = planner.plan(grid, start, goal)
        lengths[(start, goal)] = float(np.hypot(*np.diff(path, axis=0).T).sum())

    planner.plan(grid, *pairs[0])  # numba's cache loaded
    times = time_ms(once, 40, warmup=0)
    per_pair = [times[i::len(pairs)] for i in range(len(pairs))]
    return Sample(times, {"cells": int(grid.data.size), "size_m": [100.0, 30.0],
                          "end_to_end_median_ms": round(float(np.median(per_pair[0] + per_pair[1] + per_pair[2])), 3),
                          "short_10m_median_ms": round(float(np.median(per_pair[3])), 3),
                          "path_lengths_m": [round(v, 1) for v in lengths.values()]})


def _scan(occupancy: np.ndarray, pose, beams: int = 500, max_range: float = 12.0) -> LidarScan:
    """A lidar revolution ray-marched through layer costs in quarter-cell steps."""
    angles = np.linspace(-np.pi, np.pi, beams, endpoint=False).astype(np.float32)
    r = np.arange(0.0, max_range, RES / 4)
    a = pose[2] + angles.astype(np.float64)
    ix = np.floor((pose[0] + np.cos(a)[:, None] * r) / RES).astype(int)
    iy = np.floor((pose[1] + np.sin(a)[:, None] * r) / RES).astype(int)
    inside = (ix >= 0) & (ix < occupancy.shape[1]) & (iy >= 0) & (iy < occupancy.shape[0])
    hit = np.zeros(ix.shape, bool)
    hit[inside] = occupancy[iy[inside], ix[inside]] == LETHAL
    first = np.where(hit.any(axis=1), hit.argmax(axis=1), -1)
    return LidarScan(0.0, angles, np.where(first >= 0, r[np.maximum(first, 0)], np.inf).astype(np.float32))


@benchmark("nav.local_costmap")
def local_update(config: LupinConfig) -> Sample:
    """One update of the 3 x 3 m local costmap from a 500-point scan while driving down an
    aisle (the window rolls every update): clear, mark, merge, inflate."""
    world = _greenhouse(200)
    poses = [(1.0 + 0.1 * i, 1.5, 0.0) for i in range(60)]
    scans = [_scan(world, p) for p in poses]
    costmap = local_costmap(config.nav.costmap)
    k = iter(range(10 ** 9))

    def once():
        i = next(k) % len(poses)
        x, y, yaw = poses[i]
        costmap.update(scans[i], (x, y, yaw), (x, y))

    times = time_ms(once, 200)
    # Side by side: the clearing step alone for one scan, numba against vectorised numpy.
    grid = costmap.obstacle.grid
    x0, y0 = (int(v) for v in grid.geometry.cell_of(*poses[0][:2]))
    ends = np.clip(np.stack(grid.geometry.cell_of(poses[0][0] + np.cos(scans[0].angles) * 3.0,
                                               poses[0][1] + np.sin(scans[0].angles) * 3.0)), 0, grid.width - 1)
    data = np.zeros_like(grid.data)
    numba_ms = time_ms(lambda: clear_rays(data, x0, y0, ends[0], ends[1], FREE), 50)

    def numpy_clear():
        ix, iy = ray_cells(x0, y0, ends[0], ends[1])
        data[iy, ix] = FREE

    numpy_ms = time_ms(numpy_clear, 50)
    return Sample(times, {"beams": 500, "window_cells": int(grid.data.size),
                          "numba_raytrace_ms": round(float(np.median(numba_ms)), 3),
                          "numpy_raytrace_ms": round(float(np.median(numpy_ms)), 3)})
