"""The goal's recovery when MPPI finds no valid control (``nav.navigator``): clear the local
costmap, back off slowly away from the nearest obstacle for ``backoff_time``, reset the
controller and retry, at most ``max_recoveries`` times per goal (Nav2's recovery behaviours,
cut to the one this holonomic base needs). With people about, the back-off is the step to the
refuge out of everyone's way (``nav.refuge``, through ``nav.waits``), or standing still: a blind
back-off away from the nearest lethal cells, a person's disc among them, took the robot 0.7 m
diagonally into a cross aisle where a grower who does not yield was pausing, who walked into it
(safety.people seed 1, 519-525 s). A mixin, so the navigator module stays the goal's life and
these its detours, as ``nav.waits`` holds its pauses.
"""
from __future__ import annotations

import logging
import math

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from nav.costmap.grid import INSCRIBED, UNKNOWN
from nav.goal_state import State

log = logging.getLogger("nav.navigator")


class Recovery:
    """Mixed into ``nav.navigator.Navigator``: reads its ``io``, ``config``, ``local_costmap``,
    ``smoother``, ``controller`` and ``people`` (and ``nav.waits``' ``_evade``), and keeps its
    ``_recoveries``, ``_backoff`` and ``_backoff_until``."""

    def _start_recovery(self, now: float, why: str) -> None:
        if self._recoveries >= self.config.navigator.max_recoveries:
            self._finish(State.FAILED, f"no valid control after {self._recoveries} recoveries ({why})", now)
            return
        self._recoveries += 1
        log.info("recovery %d: %s; clearing the local costmap and backing off", self._recoveries, why)
        self._backoff = self._backoff_twist()
        self.local_costmap.clear()
        self.smoother.reset()
        self._backoff_until = now + self.config.navigator.backoff_time
        self._checkpoint = None
        self.state = State.RECOVERING
        self.io.publish(ZERO_TWIST, now)

    def _recover(self, now: float, dt: float) -> None:
        if now < self._backoff_until:
            layer = self.people.layer
            twist = self._evade(layer.wait_clearance, layer.lane_time) if self.people.counted() else self._backoff
            self.io.publish(self.smoother.smooth(twist, dt), now)
            return
        self.controller.reset()
        self.smoother.reset()
        self.state = State.FOLLOWING
        self.io.publish(ZERO_TWIST, now)

    def _backoff_twist(self) -> Twist:
        """Body-frame velocity away from the nearest obstacle cells in the local costmap (the
        base is holonomic, so 'back off' means away from what is closest, not just reverse)."""
        grid = self.local_costmap.grid
        odom = self.io.odom_pose()
        iy, ix = np.nonzero((grid.data >= INSCRIBED) & (grid.data != UNKNOWN))
        speed = self.config.navigator.backoff_speed
        if len(ix) == 0:
            return Twist(-speed, 0.0, 0.0)
        wx, wy = grid.geometry.centre_of(ix, iy)
        d = np.hypot(wx - odom.x, wy - odom.y)
        near = d <= d.min() + 0.15
        away = np.array([odom.x - wx[near].mean(), odom.y - wy[near].mean()])
        n = float(np.hypot(*away))
        if n < 1e-6:
            return Twist(-speed, 0.0, 0.0)
        c, s = math.cos(odom.yaw), math.sin(odom.yaw)
        bx, by = c * away[0] + s * away[1], -s * away[0] + c * away[1]
        return Twist(speed * bx / n, speed * by / n, 0.0)
