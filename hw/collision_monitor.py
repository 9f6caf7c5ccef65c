"""The collision monitor: the last check between the twist_mux and the wheels (Nav2's
nav2_collision_monitor, for this robot).

The costmaps MPPI plans on are a picture of the recent past, built through SLAM and a 5 Hz
layer; a person stepping out between two pots is in the lidar's next revolution long before
that. So every twist the mux lets through, from any source (autonomy, console, gamepad), is
checked here against the newest raw scan, on its own: no costmap, no SLAM, no planner.

Three rules, as Nav2 names them, each judged in the direction the base is commanded to move
(this base drives sideways as readily as forwards, so a zone "in front" turns with the twist):

- **stop**: ``min_points`` or more scan points in the stop zone -> the linear part of the twist
  is zeroed (turning on the spot sweeps nothing new with a circular footprint, so it stays
  allowed and lets the planner look for another way). The zone is what the footprint would
  sweep in the next ``length - radius`` metres (8 cm) of straight travel, within a box
  ``length`` ahead and ``half_width`` to either side: a pot's rim diagonally ahead that the
  robot will pass by is not in it (the box's corners stopped the 180-pot patrol 177 times at
  its pots, 8 % of its robot time);
- **slowdown**: points in the larger slowdown box -> the whole twist is scaled so the linear
  speed is at most ``slowdown.speed``;
- **approach**: the footprint (a circle of the nav footprint radius) is carried along the
  commanded twist for ``time_before_collision`` seconds in ``time_step`` steps; if it would
  touch a scan point at time ``t`` sooner than that, the twist is scaled by
  ``t / time_before_collision`` (Nav2's approach polygon: the robot keeps that much time to
  any obstacle, however fast something closes in).

A twist away from an obstacle is never held back by it (points behind the direction of travel
do not count), the monitor only ever scales or zeros (it never adds motion or turns a command),
and a scan older than ``scan_timeout`` stops the linear motion (Nav2's ``source_timeout``: a
monitor that cannot see cannot vouch for anything). The e-stop stays above it: the base
controller checks the button before it asks the monitor anything.

Cost: one scan's points into the base frame (a few hundred, vectorised) and a (steps x points)
distance table; well under a millisecond (``lupin bench safety.collision_monitor``).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from hw.config import CollisionMonitorConfig
from hw.interfaces import Lidar, LidarScan, Twist

#: Below this linear speed (m/s) the base only turns: no direction of travel, nothing to judge.
MOVING = 1e-3

NONE, SLOWDOWN, STOP, APPROACH, BLIND = "none", "slowdown", "stop", "approach", "blind"


@dataclass(frozen=True)
class Verdict:
    """What the monitor did to one twist, and why."""

    action: str
    """``none``, ``slowdown``, ``approach``, ``stop`` or ``blind`` (no fresh scan: stopped)."""
    scale: float
    """Factor applied to the linear part of the twist (0 stopped, 1 untouched)."""
    nearest: float
    """Distance from the base centre to the nearest point in the direction of travel, m (inf: none)."""

    @property
    def holding(self) -> bool:
        """The base is being kept from driving where it was told (stopped or blind)."""
        return self.action in (STOP, BLIND)


CLEAR = Verdict(NONE, 1.0, math.inf)


class CollisionMonitor:
    def __init__(self, config: CollisionMonitorConfig, lidar: Lidar, footprint_radius: float,
                 lidar_mount: tuple[float, float, float], log: logging.Logger | None = None):
        self.config = config
        self.lidar = lidar
        self.radius = footprint_radius
        self.log = log if log is not None else logging.getLogger(__name__)
        x, y, yaw = lidar_mount
        self._mount = (np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]), np.array([x, y]))
        self._scan_stamp: float | None = None
        self.points = np.empty((0, 2))
        """The newest scan's returns, base frame, m."""
        self.verdict = CLEAR
        """The last twist's verdict."""
        k = max(1, round(config.approach.time_before_collision / config.approach.time_step))
        self._times = config.approach.time_step * np.arange(1, k + 1)

    # -- the scan -----------------------------------------------------------------------------

    def take_scan(self, scan: LidarScan) -> None:
        """The scan's finite returns into the base frame (once per revolution), less those inside
        the footprint: the lidar sees the robot's own arm (the seed drops returns below 0.25 m
        for it, but with the lidar 0.115 m forward of the centre that would blind the stop zone,
        so here the footprint itself is the self-filter, as a laser box filter would be)."""
        ok = np.isfinite(scan.ranges)
        r, a = scan.ranges[ok].astype(np.float64), scan.angles[ok].astype(np.float64)
        rot, offset = self._mount
        p = np.stack([r * np.cos(a), r * np.sin(a)], axis=1) @ rot.T + offset
        self.points = p[np.einsum("ij,ij->i", p, p) >= self.radius ** 2]
        self._scan_stamp = scan.stamp

    def _fresh(self, now: float) -> bool:
        scan = self.lidar.latest_scan()
        if scan is not None and scan.stamp != self._scan_stamp:
            self.take_scan(scan)
        return self._scan_stamp is not None and now - self._scan_stamp <= self.config.scan_timeout

    # -- the twist ----------------------------------------------------------------------------

    def filter(self, twist: Twist, now: float) -> Twist:
        """The twist the wheels may have: ``twist`` scaled or stopped (never more)."""
        if not self.config.enabled:
            return twist
        speed = math.hypot(twist.vx, twist.vy)
        if speed < MOVING:
            verdict = CLEAR
        elif not self._fresh(now):
            verdict = Verdict(BLIND, 0.0, math.inf)
        else:
            verdict = self.judge(twist)
        self._note(verdict)
        if verdict.scale >= 1.0:
            return twist
        if verdict.scale <= 0.0:
            return Twist(0.0, 0.0, twist.wz)
        s = verdict.scale
        return Twist(twist.vx * s, twist.vy * s, twist.wz * s)

    def judge(self, twist: Twist) -> Verdict:
        """The verdict on ``twist`` against the current points (``filter`` without the scan)."""
        c = self.config
        speed = math.hypot(twist.vx, twist.vy)
        ux, uy = twist.vx / speed, twist.vy / speed
        p = self.points
        along = p[:, 0] * ux + p[:, 1] * uy
        across = np.abs(p[:, 1] * ux - p[:, 0] * uy)
        ahead = along > 0.0
        nearest = float(np.hypot(p[ahead, 0], p[ahead, 1]).min()) if ahead.any() else math.inf

        def in_box(zone) -> np.ndarray:
            return ahead & (along < zone.length) & (across < zone.half_width)

        # the stop box's points the footprint would touch within its last (length - radius) metres
        # of straight travel: its corners, beside that stadium, are things the robot passes by
        sweep = c.stop.length - self.radius
        swept = np.hypot(np.maximum(along - sweep, 0.0), across) < self.radius
        if np.count_nonzero(in_box(c.stop) & swept) >= c.min_points:
            return Verdict(STOP, 0.0, nearest)
        scale, action = 1.0, NONE
        if np.count_nonzero(in_box(c.slowdown)) >= c.min_points and speed > c.slowdown.speed:
            scale, action = c.slowdown.speed / speed, SLOWDOWN
        hit = self._time_to_collision(twist, p[ahead & (along < speed * c.approach.time_before_collision
                                                         + self.radius + c.approach.time_step * speed)])
        if hit is not None and hit / c.approach.time_before_collision < scale:
            scale, action = hit / c.approach.time_before_collision, APPROACH
        return Verdict(action, scale, nearest)

    def _time_to_collision(self, twist: Twist, points: np.ndarray) -> float | None:
        """When the footprint, carried along ``twist``, first touches one of ``points`` (None:
        not within the horizon). Poses come from the exact integral of a constant body twist."""
        if len(points) < self.config.min_points:
            return None
        t, w = self._times, twist.wz
        if abs(w) < 1e-6:
            cx, cy = twist.vx * t, twist.vy * t
        else:
            s, c1 = np.sin(w * t), 1.0 - np.cos(w * t)
            cx = (twist.vx * s - twist.vy * c1) / w
            cy = (twist.vy * s + twist.vx * c1) / w
        d2 = (points[None, :, 0] - cx[:, None]) ** 2 + (points[None, :, 1] - cy[:, None]) ** 2
        touching = np.count_nonzero(d2 < self.radius ** 2, axis=1) >= self.config.min_points
        return float(t[np.argmax(touching)]) if touching.any() else None

    def _note(self, verdict: Verdict) -> None:
        """Log each change of action once: a stop (or going blind) as a warning, slowing and
        clearing at debug level (a patrol slows near things all day; the status bar and the
        report's encounters show it)."""
        if verdict.action != self.verdict.action:
            level = logging.WARNING if verdict.holding else logging.DEBUG
            self.log.log(level, "collision monitor: %s (scale %.2f, nearest %.2f m)",
                         verdict.action, verdict.scale, verdict.nearest)
        self.verdict = verdict
