"""The way out of a walker's keep-out (issue 28 item 2), the navigator's side of it.

A grower who stopped for the robot at arm's length waits for it to leave their way. From inside
their keep-out the planner has no start (NavFn's ``StartBlocked``), MPPI no control (the local
costmap's disc round them takes the robot's own cell), and where no refuge is in reach
(``nav.refuge``) the robot stood: it and the grower waited for each other (safety.people seed
107, 470 s: a cart pusher and the robot for 400 s at the end of the north aisle; seed 104,
736-880 s: 150 s beside a cross aisle a walker paces). So the robot plans its way out on the map
with everyone's keep-out shrunk to where it stands (``PeopleNearby.way_out``: no step of it
comes nearer anyone) and, where MPPI finds no control, steps along it at ``NEAR_SPEED``; the
people guard and the collision monitor below bind that step as any twist. Only from someone
seen to walk: a worker who stands, or a crate on an approach pose taken for a person, does not
walk on, and is waited for as before. A mixin, as ``nav.waits``: it reads the navigator's
``people``, ``planner``, ``global_costmap``, ``keep_out``, ``goal`` and ``_way_out_at``.
"""
from __future__ import annotations

import math

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from hw.odometry import Pose2D
from nav.costmap.grid import CostGrid
from nav.people_nearby import NEAR_SPEED
from nav.planner import PlanningError, StartBlocked

#: Past a person's keep-out by this much, m, the way out of it ends.
OUT_MARGIN = 0.1
#: Turns off straight away from the nearest person, rad, tried in order for the way out: away
#: first, then ever more sideways (a wall or a pot row behind the robot), never towards them.
OUT_HEADINGS = (0.0, 0.5, -0.5, 1.0, -1.0, 1.5, -1.5)
#: How far along the way out a step out of a keep-out heads, m.
LEAVE_AHEAD = 0.3
#: Least time between two plans of the step's way out, s: the navigator's replan beat for a
#: blocked path, not every 50 ms control tick.
LEAVE_REPLAN = 0.5


class WayOut:
    def _plan(self, grid: CostGrid, pose: Pose2D) -> np.ndarray:
        """NavFn's plan to the goal; from inside a walker's keep-out (no start on ``grid``), the
        way out of it (``_way_out``, which raises ``StartBlocked`` for anyone else)."""
        try:
            return self.planner.plan(grid, (pose.x, pose.y), (self.goal.x, self.goal.y))
        except StartBlocked:
            return self._way_out(pose)

    def _way_out(self, pose: Pose2D) -> np.ndarray:
        """The head of a plan on which no step comes nearer anyone than the robot stands now, up
        to where it leaves every keep-out: towards the goal when that way leads out, else
        straight away from the nearest person, or as near that as the map allows
        (``OUT_HEADINGS``), through a fleet's open aisles only. Beyond it the next replan takes
        over, and a goal past the person waits for them as before."""
        if not self.people.in_a_walkers_keep_out(pose.x, pose.y):
            raise StartBlocked("start blocked: inside the keep-out of someone who has not walked")
        grid = self.global_costmap.without_people()
        if self.keep_out is not None:  # a fleet's aisles held by other robots stay shut on the way out
            grid = self.keep_out(grid, (pose.x, pose.y))
        grid = self.people.way_out(grid, pose.x, pose.y)
        a, _, keep_out = min(self.people.in_map(), key=lambda s: math.hypot(s[0][0] - pose.x, s[0][1] - pose.y))
        away, reach = math.atan2(pose.y - a[1], pose.x - a[0]), keep_out + OUT_MARGIN
        ends = [(self.goal.x, self.goal.y)] + [
            (a[0] + reach * math.cos(away + turn), a[1] + reach * math.sin(away + turn)) for turn in OUT_HEADINGS]
        for end in ends:
            try:
                path = self.planner.plan(grid, (pose.x, pose.y), end)
            except PlanningError:
                continue
            out = np.flatnonzero(~self.people.inside(path))
            if len(out):
                return path[:max(int(out[0]), 1) + 1]
        raise StartBlocked("start blocked: inside a person's keep-out, and no way out that keeps from them")

    def _leave(self, pose: Pose2D, now: float) -> Twist:
        """A step of ``NEAR_SPEED`` along the way out (``_way_out``, planned afresh at most every
        ``LEAVE_REPLAN``), for MPPI finding no control inside a keep-out with no refuge in reach;
        zero with no way out."""
        if now - self._way_out_at[0] >= LEAVE_REPLAN:
            try:
                self._way_out_at = (now, self._way_out(pose))
            except PlanningError:
                self._way_out_at = (now, None)
        path = self._way_out_at[1]
        if path is None:
            return ZERO_TWIST
        ahead = path[min(len(path) - 1, max(1, round(LEAVE_AHEAD / self.global_costmap.grid.resolution)))]
        heading = math.atan2(ahead[1] - pose.y, ahead[0] - pose.x) - pose.yaw
        return Twist(NEAR_SPEED * math.cos(heading), NEAR_SPEED * math.sin(heading), 0.0)
