"""Synthetic 2D lidar scans for the person tracker's tests: 500 rays (the C1's) cast at
circles (legs, pots) and line segments (walls, the sides of boxes, carts and crouching
workers), with the C1's ~1 cm range noise from a seeded generator."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

RAYS = 500
LEG_RADIUS = 0.07
POT_RADIUS = 0.10


@dataclass
class Scene:
    circles: list[tuple[float, float, float]] = field(default_factory=list)
    """(x, y, r)."""
    walls: list[tuple[float, float, float, float]] = field(default_factory=list)
    """(x0, y0, x1, y1)."""

    def legs(self, x: float, y: float, heading: float = 0.0, width: float = 0.45) -> "Scene":
        """A standing person: two legs half the body's width apart (spec/world.md)."""
        s, c = math.sin(heading), math.cos(heading)
        for side in (width / 4, -width / 4):
            self.circles.append((x - s * side, y + c * side, LEG_RADIUS))
        return self

    def box(self, x: float, y: float, sx: float, sy: float, yaw: float = 0.0) -> "Scene":
        c, s = math.cos(yaw), math.sin(yaw)
        corners = [(x + c * u - s * v, y + s * u + c * v) for u, v in
                   ((sx / 2, sy / 2), (-sx / 2, sy / 2), (-sx / 2, -sy / 2), (sx / 2, -sy / 2))]
        for a, b in zip(corners, corners[1:] + corners[:1]):
            self.walls.append((*a, *b))
        return self

    def cart_pusher(self, x: float, y: float, heading: float = 0.0, width: float = 1.0) -> "Scene":
        """Legs at (x, y) and a cart 0.6 m deep, ``width`` wide, its centre 0.45 m ahead."""
        self.legs(x, y, heading, width)
        return self.box(x + 0.45 * math.cos(heading), y + 0.45 * math.sin(heading), 0.6, width, heading)

    def crouching(self, x: float, y: float, heading: float = 0.0) -> "Scene":
        """A crouching worker: one compact 0.5 x 0.6 m body (spec/world.md)."""
        return self.box(x, y, 0.5, 0.6, heading)

    def pot_row(self, x0: float, y: float, n: int, pitch: float = 1.0) -> list[tuple[float, float]]:
        pots = [(x0 + k * pitch, y) for k in range(n)]
        self.circles += [(px, py, POT_RADIUS) for px, py in pots]
        return pots

    def scan(self, pose: tuple[float, float, float], seed: int = 0, noise: float = 0.01,
             range_max: float = 12.0) -> np.ndarray:
        """The valid returns, (N, 2) in the scene's frame, in scan order, from a lidar at ``pose``."""
        a = pose[2] + np.arange(RAYS) * (2 * math.pi / RAYS)
        d = np.stack([np.cos(a), np.sin(a)], axis=1)
        o = np.array(pose[:2])
        best = np.full(RAYS, np.inf)
        if self.circles:
            c = np.array(self.circles)
            oc = c[None, :, :2] - o
            along = d @ oc[0].T
            perp2 = (oc[0] ** 2).sum(axis=1)[None, :] - along ** 2
            half = np.sqrt(np.maximum(c[None, :, 2] ** 2 - perp2, 0))
            t = np.where((perp2 <= c[None, :, 2] ** 2) & (along - half > 0), along - half, np.inf)
            best = np.minimum(best, t.min(axis=1))
        if self.walls:
            w = np.array(self.walls)
            p, e = w[:, :2], w[:, 2:] - w[:, :2]
            cross = d[:, 0:1] * e[None, :, 1] - d[:, 1:2] * e[None, :, 0]
            q = p[None, :, :] - o
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (q[..., 0] * e[None, :, 1] - q[..., 1] * e[None, :, 0]) / cross
                u = (q[..., 0] * d[:, 1:2] - q[..., 1] * d[:, 0:1]) / cross
            t = np.where((np.abs(cross) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1), t, np.inf)
            best = np.minimum(best, t.min(axis=1))
        r = best + np.random.default_rng(seed).normal(0, noise, RAYS)
        ok = np.isfinite(best) & (r < range_max)
        return o + r[ok, None] * d[ok]


def greenhouse(length: float = 8.0, width: float = 5.0) -> Scene:
    """Four walls round a floor [0, length] x [0, width]."""
    s = Scene()
    s.walls += [(0, 0, length, 0), (length, 0, length, width), (length, width, 0, width), (0, width, 0, 0)]
    return s


def mapped(scene: Scene, floor: tuple[float, float] = (8.0, 5.0), resolution: float = 0.05):
    """The scene's walls (and the sides of its boxes) as a map_server-style occupancy grid: the
    map at patrol start, before any person walked in."""
    from nav.occupancy import OCCUPIED, OccupancyMap

    w, h = int(round(floor[0] / resolution)) + 4, int(round(floor[1] / resolution)) + 4
    grid = np.zeros((h, w), np.int8)
    for x0, y0, x1, y1 in scene.walls:
        n = int(math.hypot(x1 - x0, y1 - y0) / (resolution / 2)) + 2
        xs, ys = np.linspace(x0, x1, n), np.linspace(y0, y1, n)
        ix = np.clip(np.floor((xs + 2 * resolution) / resolution).astype(int), 0, w - 1)
        iy = np.clip(np.floor((ys + 2 * resolution) / resolution).astype(int), 0, h - 1)
        grid[iy, ix] = OCCUPIED
    return OccupancyMap(grid, resolution, -2 * resolution, -2 * resolution)
