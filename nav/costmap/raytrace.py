"""Ray tracing on a grid: the cells a lidar beam crosses, for clearing free space.

Each beam runs from the sensor's cell to its end cell, both included (Nav2's raytraceLine
visits the end cell too; the obstacle layer marks after it clears, so a return's own cell ends
up lethal). The line is the rounded DDA form of Bresenham's: ``n`` steps along the major axis,
the minor coordinate ``b0 + sign * floor((2 i |db| + n) / 2n)`` in integer arithmetic, so the two
implementations below visit exactly the same cells.

``clear_rays`` (numba) is what the obstacle layer runs; ``ray_cells`` (numpy) expands every beam
at once and is kept as the vectorised reference and for the benchmark's side-by-side: a beam's
length varies, so the numpy form pays for ragged index arithmetic over every cell of every beam.
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def clear_rays(data, x0, y0, x1, y1, value):
    """Set every cell on the lines (x0, y0) -> (x1[i], y1[i]) to ``value``; cells must be inside."""
    for i in range(x1.size):
        dx = x1[i] - x0
        dy = y1[i] - y0
        adx = abs(dx)
        ady = abs(dy)
        sx = 1 if dx > 0 else -1
        sy = 1 if dy > 0 else -1
        if adx >= ady:
            n = adx
            for s in range(n + 1):
                off = (2 * s * ady + n) // (2 * n) if n > 0 else 0
                data[y0 + sy * off, x0 + sx * s] = value
        else:
            n = ady
            for s in range(n + 1):
                off = (2 * s * adx + n) // (2 * n)
                data[y0 + sy * s, x0 + sx * off] = value


def ray_cells(x0: int, y0: int, x1: np.ndarray, y1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All cells of all lines (x0, y0) -> (x1[i], y1[i]), concatenated (ix, iy), vectorised."""
    dx, dy = np.asarray(x1, np.int64) - x0, np.asarray(y1, np.int64) - y0
    adx, ady = np.abs(dx), np.abs(dy)
    n = np.maximum(adx, ady)
    steps = n + 1
    ray = np.repeat(np.arange(n.size), steps)
    s = np.arange(ray.size) - np.repeat(np.cumsum(steps) - steps, steps)  # step index within its ray
    nr = np.maximum(n[ray], 1)
    major_x = adx[ray] >= ady[ray]
    minor = (2 * s * np.where(major_x, ady[ray], adx[ray]) + nr) // (2 * nr)
    sx, sy = np.where(dx[ray] > 0, 1, -1), np.where(dy[ray] > 0, 1, -1)
    ix = x0 + sx * np.where(major_x, s, minor)
    iy = y0 + sy * np.where(major_x, minor, s)
    return ix, iy
