"""The global planner: NavFn's Dijkstra potential field and gradient descent (seed: NavfnPlanner,
use_astar false, allow_unknown true, tolerance 0.5).

NavFn (Nav2's nav2_navfn_planner, after Konolige's gradient method) does not search a graph of
cells for a path. It spreads a *potential* outwards from the robot over the whole costmap, the
way a wavefront spreads, and then walks down that potential's gradient from the goal back to the
robot. Each cell's potential comes from its two cheapest neighbours through an interpolation of
the eikonal equation, so the field, and the path down it, are smooth rather than bent to the
grid's eight directions (MPPI's PathAlign critic hugs this path: zig-zags would make it wiggle).

Cost of crossing a cell (Nav2's navfn cost model): ``50 + 0.8 * cost`` for costmap costs below
253, capped at 253; inscribed (253) and lethal (254) cells are impassable; unknown (255) costs 253
when ``allow_unknown`` (nearly impassable: explored ground is always preferred) and is impassable
otherwise. The robot's own cell counts as free (Nav2 clears it: the robot is there, so it is not
an obstacle).

Propagation order is NavFn's: cells wait in a "current" and a "next" buffer below a threshold
and in an "overflow" buffer above it; the threshold rises by twice the neutral cost each time the
current level empties. It is a bucketed, nearly exact Dijkstra in O(cells), stopped as soon as the
goal has a potential. When the goal cannot be reached (it lies in an inscribed or lethal cell, or
is walled off), the whole reachable area is covered and the plan ends at the reachable cell
nearest the goal within ``tolerance`` (a disc; Nav2 scans the square around it).

The wavefront and the descent cannot be vectorised (each step depends on the last), so they are
compiled with numba; the path is then resampled to one point per cell. ``lupin bench
nav.plan_400``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from nav.config import PlannerConfig
from nav.costmap.grid import INSCRIBED, UNKNOWN, CostGrid

NEUTRAL = 50
"""NavFn's COST_NEUTRAL: the cost of crossing a free cell."""
FACTOR = 0.8
"""NavFn's COST_FACTOR: costmap cost to crossing cost."""
OBSTACLE = 254
"""NavFn's COST_OBS: impassable."""
POT_HIGH = np.float32(1.0e10)
"""Potential of a cell the wavefront has not reached."""
STALL_STEPS = 8
"""Half-cell descent steps without reaching a lower cell before a step to the lowest neighbour."""


class PlanningError(Exception):
    """No plan; ``str(exc)`` says why in a few words (start blocked, no path, ...)."""


class StartBlocked(PlanningError):
    """Every cell round the robot is taken: something against it (someone who walked up to it,
    a cart pushed past it), not a route that is closed; the navigator waits it out."""


def crossing_costs(data: np.ndarray, allow_unknown: bool) -> np.ndarray:
    """NavFn's per-cell crossing cost (uint8) from Nav2 costmap values."""
    v = np.arange(256)
    table = np.minimum(NEUTRAL + (FACTOR * v).astype(np.int64), OBSTACLE - 1)
    table[INSCRIBED:] = OBSTACLE
    if allow_unknown:
        table[UNKNOWN] = OBSTACLE - 1
    return table.astype(np.uint8)[data]


class NavfnPlanner:
    def __init__(self, config: PlannerConfig):
        self.config = config

    def plan(self, grid: CostGrid, start_xy, goal_xy) -> np.ndarray:
        """(N, 2) world points from ``start_xy`` to the goal (or to the reachable point nearest it
        within tolerance), about one per cell. Raises ``PlanningError``."""
        geo = grid.geometry
        (sx,), (sy,) = (np.atleast_1d(a) for a in geo.cell_of(start_xy[0], start_xy[1]))
        (gx,), (gy,) = (np.atleast_1d(a) for a in geo.cell_of(goal_xy[0], goal_xy[1]))
        if not geo.contains(sx, sy):
            raise PlanningError("start outside the costmap")
        if not geo.contains(gx, gy):
            raise PlanningError("goal outside the costmap")
        h, w = grid.data.shape
        cost = np.full((h + 2, w + 2), OBSTACLE, dtype=np.uint8)  # an impassable frame around the map
        cost[1:-1, 1:-1] = crossing_costs(grid.data, self.config.allow_unknown)
        cost[sy + 1, sx + 1] = NEUTRAL
        start, goal = (sy + 1) * (w + 2) + sx + 1, (gy + 1) * (w + 2) + gx + 1
        pot = propagate(cost.ravel(), w + 2, start, goal)
        if not (pot < POT_HIGH).sum() > 1 and start != goal:
            raise StartBlocked("start blocked: every cell around the robot is inscribed or lethal")
        pot2 = pot.reshape(h + 2, w + 2)
        if pot2[gy + 1, gx + 1] < POT_HIGH:
            tx, ty, end = gx, gy, np.asarray(goal_xy[:2], dtype=float)
        else:
            tx, ty = self._nearest_reachable(grid, pot2[1:-1, 1:-1], goal_xy, gx, gy)
            end = np.array(geo.centre_of(tx, ty), dtype=float)
        cells = descend(pot, cost.ravel(), w + 2, float(tx + 1), float(ty + 1), float(sx + 1), float(sy + 1))
        if cells.shape[0] == 0:
            raise PlanningError("no path: the descent got stuck")  # a bug, but never crash the loop
        xy = np.column_stack(geo.centre_of(cells[::-1, 0] - 1.0, cells[::-1, 1] - 1.0))
        xy[0], xy[-1] = start_xy[:2], end
        return resample(xy, grid.resolution)

    def _nearest_reachable(self, grid: CostGrid, pot: np.ndarray, goal_xy, gx: int, gy: int) -> tuple[int, int]:
        r = int(math.ceil(self.config.tolerance / grid.resolution))
        x0, y0 = max(gx - r, 0), max(gy - r, 0)
        win = pot[y0:gy + r + 1, x0:gx + r + 1]
        iy, ix = np.mgrid[y0:y0 + win.shape[0], x0:x0 + win.shape[1]]
        wx, wy = grid.geometry.centre_of(ix, iy)
        d = np.hypot(wx - goal_xy[0], wy - goal_xy[1])
        ok = (win < POT_HIGH) & (d <= self.config.tolerance)
        if not ok.any():
            blocked = grid.data[gy, gx] >= INSCRIBED and not (self.config.allow_unknown and grid.data[gy, gx] == UNKNOWN)
            raise PlanningError("goal blocked beyond tolerance" if blocked else "no path to the goal")
        k = int(np.argmin(np.where(ok, d, np.inf)))
        return int(ix.flat[k]), int(iy.flat[k])


def resample(xy: np.ndarray, step: float) -> np.ndarray:
    """Points every ``step`` metres along the polyline ``xy``, both ends kept."""
    seg = np.hypot(*np.diff(xy, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    if s[-1] < 1e-9:
        return xy[[0, -1]].copy()
    n = max(int(math.ceil(s[-1] / step)), 1)
    t = np.linspace(0.0, s[-1], n + 1)
    return np.column_stack([np.interp(t, s, xy[:, 0]), np.interp(t, s, xy[:, 1])])


@njit(cache=True)
def propagate(cost, nx, start, goal):
    """NavFn's Dijkstra wavefront from ``start`` over a flat, framed cost array; stops once
    ``goal`` has a potential (``goal`` -1: covers everything reachable). Returns the potential
    (float32, POT_HIGH where unreached)."""
    ns = cost.size
    pot = np.full(ns, POT_HIGH, dtype=np.float32)
    pending = np.zeros(ns, dtype=np.bool_)
    bufs = np.empty((3, ns), dtype=np.int64)
    counts = np.zeros(3, dtype=np.int64)
    cur, nxt, over = 0, 1, 2
    inc = np.float32(2 * NEUTRAL)
    threshold = inc
    pot[start] = 0.0
    for m in (start - 1, start + 1, start - nx, start + nx):
        if cost[m] < OBSTACLE and not pending[m]:
            bufs[cur, counts[cur]] = m
            counts[cur] += 1
            pending[m] = True
    while counts[cur] > 0 or counts[nxt] > 0:
        for i in range(counts[cur]):
            pending[bufs[cur, i]] = False
        for i in range(counts[cur]):
            n = bufs[cur, i]
            left, right, down, up = pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
            a = min(left, right)
            b = min(down, up)
            lo = min(a, b)
            gap = abs(a - b)
            hf = np.float32(cost[n])
            if gap >= hf:
                p = lo + hf
            else:
                t = gap / hf
                p = lo + hf * np.float32(-0.2301 * t * t + 0.5307 * t + 0.7040)
            if p >= pot[n]:
                continue
            pot[n] = p
            target = nxt if p < threshold else over
            for m in (n - 1, n + 1, n - nx, n + nx):
                if cost[m] < OBSTACLE and not pending[m] and pot[m] > p + np.float32(0.70710678) * cost[m]:
                    bufs[target, counts[target]] = m
                    counts[target] += 1
                    pending[m] = True
        counts[cur] = 0
        cur, nxt = nxt, cur
        if counts[cur] == 0:
            threshold += inc
            cur, over = over, cur
        if goal >= 0 and pot[goal] < POT_HIGH:
            break
    return pot


@njit(cache=True)
def _gradient(pot, cost, nx, n):
    """Normalised downhill-pointing gradient of the potential at cell n (unreached neighbours
    count as the cell's potential plus an obstacle's cost, so the gradient points away)."""
    p = pot[n]
    high = p + np.float32(OBSTACLE)
    l_, r_, d_, u_ = pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
    l_ = high if l_ >= POT_HIGH else l_
    r_ = high if r_ >= POT_HIGH else r_
    d_ = high if d_ >= POT_HIGH else d_
    u_ = high if u_ >= POT_HIGH else u_
    gx = (r_ - l_) * 0.5
    gy = (u_ - d_) * 0.5
    norm = math.sqrt(gx * gx + gy * gy)
    if norm <= 0.0:
        return 0.0, 0.0
    return gx / norm, gy / norm


@njit(cache=True)
def descend(pot, cost, nx, x, y, sx, sy):
    """Walk down the potential from (x, y) (framed cell coordinates, centres at integers) to the
    start (sx, sy) in half-cell steps; returns the visited points, goal first. Where any of the
    eight cells around is unreached (next to an obstacle) or the walk oscillates, it steps to the
    lowest neighbour instead, as NavFn does; so it does when the cell under it has not got lower
    for ``STALL_STEPS`` steps (the interpolated gradient can circle a saddle where known floor
    meets unknown ground, 50 against 253 a cell, without ever repeating a point exactly)."""
    limit = 4 * pot.size
    out = np.empty((4096, 2), dtype=np.float64)
    out[0, 0], out[0, 1] = x, y
    k = 1
    lowest, stalled = POT_HIGH, 0
    for _ in range(limit):
        if k + 2 > out.shape[0]:
            grown = np.empty((2 * out.shape[0], 2), dtype=np.float64)
            grown[:k] = out[:k]
            out = grown
        if abs(x - sx) <= 1.0 and abs(y - sy) <= 1.0:
            out[k, 0], out[k, 1] = sx, sy
            return out[:k + 1]
        cx, cy = int(math.floor(x + 0.5)), int(math.floor(y + 0.5))
        n = cy * nx + cx
        near_edge = False
        for m in (n - 1, n + 1, n - nx, n + nx, n - nx - 1, n - nx + 1, n + nx - 1, n + nx + 1):
            if pot[m] >= POT_HIGH:
                near_edge = True
        if pot[n] < lowest:
            lowest, stalled = pot[n], 0
        else:
            stalled += 1
        oscillating = (k >= 3 and abs(out[k - 2, 0] - x) + abs(out[k - 2, 1] - y) < 0.2) or stalled >= STALL_STEPS
        moved = False
        if not near_edge and not oscillating:
            fx, fy = int(math.floor(x)), int(math.floor(y))
            ax, ay = x - fx, y - fy
            g00 = _gradient(pot, cost, nx, fy * nx + fx)
            g10 = _gradient(pot, cost, nx, fy * nx + fx + 1)
            g01 = _gradient(pot, cost, nx, (fy + 1) * nx + fx)
            g11 = _gradient(pot, cost, nx, (fy + 1) * nx + fx + 1)
            gx = (1 - ay) * ((1 - ax) * g00[0] + ax * g10[0]) + ay * ((1 - ax) * g01[0] + ax * g11[0])
            gy = (1 - ay) * ((1 - ax) * g00[1] + ax * g10[1]) + ay * ((1 - ax) * g01[1] + ax * g11[1])
            norm = math.sqrt(gx * gx + gy * gy)
            if norm > 1e-6:
                x -= 0.5 * gx / norm
                y -= 0.5 * gy / norm
                moved = True
        if not moved:
            best, bm = pot[n], -1
            for m in (n - 1, n + 1, n - nx, n + nx, n - nx - 1, n - nx + 1, n + nx - 1, n + nx + 1):
                if pot[m] < best:
                    best, bm = pot[m], m
            if bm < 0:
                return out[:0]
            x, y = float(bm % nx), float(bm // nx)
        out[k, 0], out[k, 1] = x, y
        k += 1
    return out[:0]
