"""Where to wait for people: the nearest free spot out of everyone's way (issue 28 item 2).

A step out of one person's way is only safe if it does not lead into another's. safety.people's
seed 4 showed how it goes wrong: the robot, waiting for a grower who had stopped for it at the
mouth of their aisle, backed off from them along a fan of directions and so into the cross aisle
a cart pusher walks without yielding, who then shoved it 2.3 m along the floor; and stepping
"square to a walker's way" needs room on that side, which a cross aisle between a wall and the
row ends does not have. So the step is not a direction but a place: of every cell the robot can
reach in the local costmap (NavFn's wavefront from the robot, ``nav.planner.propagate``), the
nearest by path whose centre is

* clear of every walker's walk: their straight line ``lane_time`` seconds on *and back* (people
  pace: a cart pusher at the end of a cross aisle turns and comes back down it) by the person
  layer's keep-out plus ``TOUCH``, and as clear of the circles people were seen to turn round
  in (``nav.walks``: a lane ends where its walker turns, and a cart swings round its pusher
  there, wider than the lane); and
* at least ``want`` body to body from everyone (the wider ``wait_clearance`` while the robot waits
  for someone, when there is such a place in reach; else the layer's ``clearance`` plus
  ``MARGIN``).

The way there keeps ``clearance`` less ``TOUCH`` from everyone (or, with someone come nearer, no
nearer than they are now), and never goes deeper into the way ahead of a walker (their line
``lane_time`` on, not back) than the robot stands: out of it on its own side, or on along it,
never across in front of them. Behind a walker it may cross their lane to a refuge beyond: a
grower who had stopped for the robot in their aisle waited for it for good while the only way
out crossed the far end of a cross aisle a cart pusher was walking away along (safety.people
seed 1, 70-2200 s: 2,100 s of mutual waiting, 24 pots lost). A robot already standing
in the best such place stays, and one heading for a refuge keeps heading for it while it stays
one (``STICK``, ``SLACK``); with no such place in reach it stands still (standing, a walker who does not yield walks into it, which the judges
count apart: moving into them is the robot's doing).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from nav.costmap.grid import CostGrid
from nav.planner import NEUTRAL, OBSTACLE, POT_HIGH, crossing_costs, descend, propagate

#: A walk passing nearer than this to the robot's body would touch it, m: a few tracker jitters.
TOUCH = 0.05
#: Past ``clearance``, the least room to everyone a refuge has when none in reach has ``want``, m.
MARGIN = 0.1
#: The step heads for the point this far along the way to the refuge, m.
LOOK = 0.3
#: A refuge chosen before is kept while it is still a refuge and at most this much farther by
#: path than the nearest, m. Chosen afresh each tick, the refuge flipped from one side of a cart
#: pusher's lane to the other as the tracker's estimate of their heading swung +-15 deg, and
#: the robot, stepping west, east, west, stood in the lane until the cart walked into it
#: (safety.people seed 2, 1,403-1,407 s: the steps alternated 10 times in 3 s).
STICK = 0.5
#: How much nearer to a lane, or to someone, a refuge already headed for may come before it is
#: given up, m: the nearest refuge is at the edge of a lane by its choosing, so any swing of a
#: walker's heading estimate towards it would give it up (down to ``clearance`` + ``TOUCH`` -
#: ``SLACK``, 0.25 m body to body from the lane: issue 28's least clearance while moving).
SLACK = 0.1
#: A person's walking pace, m/s (the sim's walkers 0.6-1.1): a lane reaches ``lane_time`` at
#: this pace at least, so a walker slowing to turn at the end of their walk, whom the tracker
#: still sees creeping at 0.25 m/s, keeps the whole lane they walk.
PACE = 1.0
#: The most a body reaches across its walk, m: a cart pusher's tracked circle holds the cart's
#: length too (up to ~0.8 m), but the lane is as wide as the cart (0.35 m) and its pusher's legs.
ACROSS = 0.45


class Step(NamedTuple):
    heading: np.ndarray | None
    """Unit direction (odom) of the first stretch of the way to the refuge; None: it is here."""
    refuge: np.ndarray
    """The refuge's centre (odom): ``keep`` for the next tick's choice."""


def refuge_heading(here: np.ndarray, people: np.ndarray, grid: CostGrid, robot_radius: float,
                   clearance: float, want: float, lane_time: float, walking: float,
                   keep: np.ndarray | None = None, turns: np.ndarray | None = None) -> Step | None:
    """The step towards the nearest refuge (module docstring) from ``here``, or None: none is
    in reach.

    ``people``: (P, 5) rows of x, y, vx, vy, radius in ``grid``'s frame; ``clearance`` the person
    layer's body-to-body keep-out, ``want`` the distance to wait at when there is room for it;
    a person faster than ``walking`` m/s walks a lane; ``keep``: the refuge the last step headed
    for, kept while it is still one within ``SLACK`` and not ``STICK`` farther than the nearest;
    ``turns``: (T, 3) rows of x, y, reach of where people turned round (``nav.walks``)."""
    geo = grid.geometry
    h, w = grid.data.shape
    iy, ix = np.mgrid[0:h, 0:w]
    cx, cy = geo.centre_of(ix, iy)
    gap = _gaps(cx, cy, people, robot_radius)
    lane = _lane_gaps(cx, cy, people, robot_radius, lane_time, walking).min(axis=0, initial=np.inf)
    lane = np.minimum(lane, _gaps(cx, cy, np.empty((0, 3)) if turns is None else turns, robot_radius))
    ahead = _lane_gaps(cx, cy, people, robot_radius, lane_time, walking, back=False)
    (sx,), (sy,) = (np.atleast_1d(a) for a in geo.cell_of(here[0], here[1]))
    if not geo.contains(sx, sy):
        return None
    cost = np.full((h + 2, w + 2), OBSTACLE, dtype=np.uint8)
    near = min(clearance - TOUCH, float(gap[sy, sx]) - TOUCH)  # never nearer anyone than it is now
    inside = np.minimum(clearance + TOUCH, ahead[:, sy, sx] - TOUCH)  # nor deeper into the way ahead of any walker
    deeper = (ahead < inside[:, None, None]).any(axis=0)
    cost[1:-1, 1:-1] = np.where((gap < near) | deeper, OBSTACLE, crossing_costs(grid.data, False))
    cost[sy + 1, sx + 1] = NEUTRAL
    framed = propagate(cost.ravel(), w + 2, (sy + 1) * (w + 2) + sx + 1, -1)
    pot = framed.reshape(h + 2, w + 2)[1:-1, 1:-1]
    kept = _cell(keep, geo)
    for need in sorted({want, clearance + MARGIN}, reverse=True):
        safe = _refuges(lane, gap, pot, clearance + TOUCH, need)
        if safe[sy, sx]:
            return Step(None, np.array(geo.centre_of(sx, sy), dtype=float))  # already there
        if not safe.any():
            continue
        k = divmod(int(np.argmin(np.where(safe, pot, np.inf))), w)
        if kept is not None and _refuges(lane, gap, pot, clearance + TOUCH - SLACK, need - SLACK)[kept] \
                and pot[kept] <= pot[k] + NEUTRAL * STICK / geo.resolution:
            k = kept
        refuge = np.array(geo.centre_of(k[1], k[0]), dtype=float)
        if k == kept and max(abs(k[0] - sy), abs(k[1] - sx)) <= 1:
            return Step(None, refuge)  # at the refuge headed for, or a cell off it
        u = _first_stretch(framed, cost, w, k[0] * w + k[1], (sx, sy), geo)
        return None if u is None else Step(u, refuge)
    return None


def _refuges(lane: np.ndarray, gap: np.ndarray, pot: np.ndarray, off_lanes: float, need: float) -> np.ndarray:
    """Cells in reach (``pot``) at least ``off_lanes`` from every walker's lane and ``need``
    from everyone, body to body."""
    return (lane >= off_lanes) & (gap >= need) & (pot < POT_HIGH)


def _cell(point: np.ndarray | None, geo) -> tuple[int, int] | None:
    """(row, column) of ``point``'s cell, None for no point or one off the grid."""
    if point is None:
        return None
    (kx,), (ky,) = (np.atleast_1d(a) for a in geo.cell_of(point[0], point[1]))
    return (int(ky), int(kx)) if geo.contains(kx, ky) else None


def _gaps(cx: np.ndarray, cy: np.ndarray, people: np.ndarray, robot_radius: float) -> np.ndarray:
    """Body-to-body distance from a robot centred on each cell to the nearest of ``people`` (rows
    of x, y, ..., radius), m."""
    out = np.full(cx.shape, np.inf)
    for x, y, *_, r in people:
        out = np.minimum(out, np.hypot(cx - x, cy - y) - r - robot_radius)
    return out


def _lane_gaps(cx: np.ndarray, cy: np.ndarray, people: np.ndarray, robot_radius: float, lane_time: float,
               walking: float, back: bool = True) -> np.ndarray:
    """(W, H, W) per walker: body-to-body distance from a robot on each cell to their lane (their
    line ``lane_time`` on and, with ``back``, back, at ``PACE`` at least, ``ACROSS`` wide at most
    each side), m; none with no one walking. Per walker, not the nearest lane: standing deep in one
    walker's lane must not let the way go deeper into another's."""
    out = []
    for x, y, vx, vy, r in people:
        speed = np.hypot(vx, vy)
        if speed <= walking:
            continue
        reach = lane_time * max(speed, PACE) / speed
        behind = reach if back else 0.0
        ax, ay, bx, by = x - vx * behind, y - vy * behind, x + vx * reach, y + vy * reach
        dx, dy = bx - ax, by - ay
        t = np.clip(((cx - ax) * dx + (cy - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
        out.append(np.hypot(cx - ax - t * dx, cy - ay - t * dy) - min(r, ACROSS) - robot_radius)
    return np.array(out).reshape(-1, *cx.shape)


def _first_stretch(framed: np.ndarray, cost: np.ndarray, w: int, k: int, start: tuple[int, int], geo) -> np.ndarray | None:
    """Unit direction to the point ``LOOK`` along the way (down the wavefront's potential
    ``framed``, on the framed grid ``cost`` is) to inner cell ``k``: from the start cell's
    centre, the way's own lattice, so a way straight along an axis is a step straight along it."""
    ty, tx = divmod(k, w)
    cells = descend(framed, cost.ravel(), w + 2, float(tx + 1), float(ty + 1),
                    float(start[0] + 1), float(start[1] + 1))
    if cells.shape[0] == 0:
        return None
    xy = np.column_stack(geo.centre_of(cells[::-1, 0] - 1.0, cells[::-1, 1] - 1.0))
    origin = np.array(geo.centre_of(start[0], start[1]), dtype=float)
    d = np.hypot(xy[:, 0] - origin[0], xy[:, 1] - origin[1])
    far = np.nonzero(d >= LOOK)[0]
    v = (xy[far[0]] if len(far) else xy[-1]) - origin
    n = float(np.hypot(*v))
    return v / n if n > 1e-6 else None
