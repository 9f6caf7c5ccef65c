"""Where people who pace turn round: closed to the planner when there is a way round them.

Workers in a greenhouse pace: a cart pusher walks a cross aisle, turns at its end, walks it back.
The person layer costs people where they are and along their walks (``nav.costmap.people``), not
where they turn, and the ends of cross aisles are where the short ways between bays run. On
``safety.people`` seeds 114 and 115 both walkers who do not yield pace the cross aisles either
side of the bay divider (x 6 and 8 m, y 2-6.5 m) and turn at its north end, the only short way
between the bays, while its south end is clear of both: the robot tried the north way again and
again (seed 115 at stop 62: from 290 s to past 400 s back and forth in W6's aisle; seed 114:
P23's approach timed out twice from bay 2, then P22's), and NavFn's dearest cell is only about
five times a free one's, so a cost there does not send it the long way.

So each drive's plan first closes every turning place remembered (``nav.walks.Walks.turns``, the
circle a turning body sweeps, held ``TURN_KEPT`` after it was last seen) out to its reach plus the
robot's radius, lethal, as a fleet's held aisles are closed (``mission.patrol.aisle_gate``); a
turning place that holds the robot or the goal stays open (the robot must be able to leave it,
and to arrive: closed, a goal inside one was "blocked" and its pot lost, in a trial at stop 62).
When no way round remains, the plan goes through them (``Navigator._plan_round_turns``): the
people rules hold wherever a person is, a turning place is only where one may be.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from nav.costmap.grid import LETHAL, CostGrid


def close_turns(grid: CostGrid, turns: Sequence[tuple[float, float, float]], robot_radius: float,
                open_at: Sequence[tuple[float, float]]) -> CostGrid | None:
    """``grid`` with each turning place ``turns`` ((x, y, reach), the grid's frame) lethal out to
    ``reach + robot_radius``, save those holding a point of ``open_at`` (the robot, the goal);
    None when there is none to close."""
    closing = [(x, y, reach + robot_radius) for x, y, reach in turns
               if all(np.hypot(px - x, py - y) > reach + robot_radius for px, py in open_at)]
    if not closing:
        return None
    data, res = grid.data.copy(), grid.resolution
    h, w = data.shape
    for x, y, r in closing:
        x0, x1 = max(int((x - r - grid.origin_x) / res), 0), min(int((x + r - grid.origin_x) / res) + 1, w)
        y0, y1 = max(int((y - r - grid.origin_y) / res), 0), min(int((y + r - grid.origin_y) / res) + 1, h)
        if x0 >= x1 or y0 >= y1:
            continue
        cx = grid.origin_x + (np.arange(x0, x1) + 0.5) * res
        cy = grid.origin_y + (np.arange(y0, y1)[:, None] + 0.5) * res
        window = data[y0:y1, x0:x1]
        window[np.hypot(cx - x, cy - y) <= r] = LETHAL
    return CostGrid(data, res, grid.origin_x, grid.origin_y)
