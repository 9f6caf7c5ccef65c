"""Has the robot arrived? Nav2's SimpleGoalChecker, stateful.

Position within ``xy_tolerance`` (0.25 m) and heading within ``yaw_tolerance`` (0.12 rad; the
seed's tight value, which frames the AprilTag head-on; see ``GoalCheckerConfig`` for the 0.18
rad fallback and why we do not take it). Stateful like Nav2's default: once the position has
been inside its tolerance, only the heading is checked until ``reset()``, so a robot squaring up
its heading is not sent back because the turn nudged it a centimetre past the xy circle.
Stopped like Nav2's StoppedGoalChecker: the robot must also be at rest (measured twist), so a
goal ends where MPPI brought the robot to a stop, not where it first crossed the circle.
"""
from __future__ import annotations

import math

from hw.interfaces import ZERO_TWIST, Twist
from hw.odometry import Pose2D
from nav.config import GoalCheckerConfig
from nav.frames import distance, yaw_error


class GoalChecker:
    def __init__(self, config: GoalCheckerConfig):
        self.config = config
        self._xy_latched = False
        self.xy_tolerance = config.xy_tolerance
        """This goal's position tolerance: the config's, or a tighter one the goal asked for."""

    def reset(self, xy_tolerance: float | None = None) -> None:
        self._xy_latched = False
        self.xy_tolerance = self.config.xy_tolerance if xy_tolerance is None else xy_tolerance

    def reached(self, pose: Pose2D, goal: Pose2D, twist: Twist = ZERO_TWIST) -> bool:
        c = self.config
        if not self._xy_latched and distance(pose, goal) <= self.xy_tolerance:
            self._xy_latched = True
        stopped = math.hypot(twist.vx, twist.vy) <= c.stopped_velocity and abs(twist.wz) <= c.stopped_yaw_rate
        return self._xy_latched and yaw_error(pose, goal) <= c.yaw_tolerance and stopped
