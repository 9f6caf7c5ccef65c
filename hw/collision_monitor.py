"""The collision monitor: the last check between the twist_mux and the wheels (Nav2's
nav2_collision_monitor, for this robot).

The costmaps MPPI plans on are a picture of the recent past, built through SLAM and a 5 Hz
layer; a person stepping out between two pots is in the lidar's next revolution long before
that. So every twist the mux lets through, from any source (autonomy, console, gamepad), is
checked here against the newest raw scan, on its own: no costmap, no SLAM, no planner.

Three rules, as Nav2 names them, each judged in the direction the base is commanded to move
(this base drives sideways as readily as forwards, so a zone "in front" turns with the twist):

- **stop**: ``min_points`` or more scan points in the stop zone -> the linear part of the twist
  is zeroed; the turn is judged on its own (below), so a turn that sweeps nothing stays allowed
  and lets the planner look for another way. The zone is what the outline would sweep going
  straight until the chassis' leading edge reaches the end of a box ``length`` ahead and
  ``half_width`` to either side (13.5 cm ahead, 17 cm sideways; a 0.22 m circle swept 8 cm): a pot's rim diagonally ahead that the robot will pass by is
  not in it (the box's corners stopped the 180-pot patrol 177 times at its pots, 8 % of its
  robot time);
- **slowdown**: points in the larger slowdown box -> the whole twist is scaled so the linear
  speed is at most ``slowdown.speed``;
- **approach**: the outline is carried along the commanded twist for
  ``time_before_collision`` seconds in ``time_step`` steps; if it would touch a scan point at
  time ``t`` sooner than that, the twist is scaled by ``t / time_before_collision`` (Nav2's
  approach polygon: the robot keeps that much time to any obstacle, however fast something
  closes in);
- **turn**: a turn (on the spot, or the turn of a stopped twist) is carried the same way: the
  chassis' corners reach 0.21 m from the centre and an outstretched arm further, so turning
  beside a leg or a post hits it. Contact within the first step zeroes ``wz``, later scales it.

The outline (``hw.robot_outline``) is the chassis rectangle plus the arm as it stands, handed in
as data from above (``arm``: a callable returning the arm's capsules from its joint states). It
is also the self-filter: returns within ``self_margin`` of it are the robot's own and dropped
(not a 0.22 m circle, which hid a leg 5-9 cm off the chassis' side).

A twist away from an obstacle is never held back by it (points behind the direction of travel
do not count), the monitor only ever scales or zeros (it never adds motion or turns a command),
and a scan that cannot be trusted stops the linear motion: one older than ``scan_timeout``
(Nav2's ``source_timeout``: a monitor that cannot see cannot vouch for anything), or one that
arrived on time blind (``hw.scan_trust``: covered, sun-blinded; zero points is not "clear").
``untrusted_since`` is the runtime time the scans stopped being trustworthy (None while they
are), for whoever above must act on a lidar that stays lost; ``fault`` names why
(``lidar_blind``, ``lidar_stale``). Both are brought up to date each base tick (``check``). The e-stop stays above it: the base
controller checks the button before it asks the monitor anything.

Cost: one scan's points into the base frame (a few hundred, vectorised) and a (steps x points)
outline test; well under a millisecond (``lupin bench safety.collision_monitor``).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from hw.config import CollisionMonitorConfig
from hw.interfaces import Lidar, LidarScan, Twist
from hw.robot_outline import NO_CAPSULES, Capsules, Outline
from hw.scan_trust import ScanTrust

#: Below this linear speed (m/s) the base only turns: no direction of travel, nothing to judge.
MOVING = 1e-3
#: Below this turn rate (rad/s) the base does not turn.
TURNING = 1e-3
#: The straight sweep of the stop zone is tested at this step, m (the outline's offsets).
SWEEP_STEP = 0.01

NONE, SLOWDOWN, STOP, APPROACH, BLIND = "none", "slowdown", "stop", "approach", "blind"
LIDAR_BLIND, LIDAR_STALE = "lidar_blind", "lidar_stale"


@dataclass(frozen=True)
class Verdict:
    """What the monitor did to one twist, and why."""

    action: str
    """``none``, ``slowdown``, ``approach``, ``stop`` or ``blind`` (no trustworthy scan: stopped)."""
    scale: float
    """Factor applied to the linear part of the twist (0 stopped, 1 untouched)."""
    nearest: float
    """Distance from the base centre to the nearest point in the direction of travel, m (inf: none)."""
    turn: float = 1.0
    """Factor applied to the turn rate ``wz`` (0: the turn would hit something at once)."""

    @property
    def holding(self) -> bool:
        """The base is being kept from driving where it was told (stopped or blind)."""
        return self.action in (STOP, BLIND)


CLEAR = Verdict(NONE, 1.0, math.inf)


class CollisionMonitor:
    def __init__(self, config: CollisionMonitorConfig, lidar: Lidar, footprint_radius: float,
                 lidar_mount: tuple[float, float, float], log: logging.Logger | None = None,
                 arm: Callable[[], Capsules] | None = None):
        self.config = config
        self.lidar = lidar
        self.radius = footprint_radius
        """The navigation footprint's radius (kept for callers; the outline is the body now)."""
        self.arm = arm
        """The arm's outline as it stands (None: a robot without one)."""
        self.log = log if log is not None else logging.getLogger(__name__)
        x, y, yaw = lidar_mount
        self._mount = (np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]), np.array([x, y]))
        self._scan_stamp: float | None = None
        self.points = np.empty((0, 2))
        """The newest scan's returns off the robot, base frame, m."""
        self.verdict = CLEAR
        """The last twist's verdict."""
        self.trust = ScanTrust(config.blind)
        self.blind_reason: str | None = None
        """Why the newest scan is blind (None: it can be trusted)."""
        self.fault: str | None = None
        """``lidar_blind``, ``lidar_stale`` or None, as of the last ``check``."""
        self.untrusted_since: float | None = None
        """Runtime time the scans stopped being trustworthy (blind or stale); None while they are."""
        self.outline = self._outline()
        k = max(1, round(config.approach.time_before_collision / config.approach.time_step))
        self._times = config.approach.time_step * np.arange(1, k + 1)

    def _outline(self) -> Outline:
        half_length, half_width = self.config.chassis
        return Outline(half_length, half_width, self.arm() if self.arm is not None else NO_CAPSULES)

    # -- the scan -----------------------------------------------------------------------------

    def take_scan(self, scan: LidarScan) -> None:
        """Judge the scan's trust, then its finite returns into the base frame (once per
        revolution), less those on the robot's own outline as it stands now (the chassis and the
        arm: the lidar sees the arm's brackets in every pose and the forearm at ``tuck``)."""
        ok = np.isfinite(scan.ranges)
        self.blind_reason = self.trust.judge(scan.angles, ok)
        r, a = scan.ranges[ok].astype(np.float64), scan.angles[ok].astype(np.float64)
        rot, offset = self._mount
        p = np.stack([r * np.cos(a), r * np.sin(a)], axis=1) @ rot.T + offset
        self.outline = self._outline()
        self.points = p[~self.outline.inside(p[:, 0], p[:, 1], self.config.self_margin)]
        self._scan_stamp = scan.stamp

    def check(self, now: float) -> bool:
        """Take a new scan if one came, and bring ``fault`` and ``untrusted_since`` up to
        ``now``; True while the scans can be trusted."""
        scan = self.lidar.latest_scan() if self.lidar is not None else None
        if scan is not None and scan.stamp != self._scan_stamp:
            self.take_scan(scan)
        stamp = self._scan_stamp
        if stamp is None or now - stamp > self.config.scan_timeout:
            fault, since = LIDAR_STALE, (now if stamp is None else stamp + self.config.scan_timeout)
        elif self.blind_reason is not None:
            fault, since = LIDAR_BLIND, stamp
        else:
            fault, since = None, None
        if fault != self.fault:
            self._note_fault(fault, now)
            self.untrusted_since = None if fault is None else (self.untrusted_since or since)
        self.fault = fault
        return fault is None

    # -- the twist ----------------------------------------------------------------------------

    def filter(self, twist: Twist, now: float) -> Twist:
        """The twist the wheels may have: ``twist`` scaled or stopped (never more)."""
        trusted = self.check(now)
        if not self.config.enabled:
            return twist
        speed = math.hypot(twist.vx, twist.vy)
        if speed < MOVING and abs(twist.wz) < TURNING:
            verdict = CLEAR
        elif not trusted:
            verdict = Verdict(BLIND, 0.0, math.inf) if speed >= MOVING else CLEAR
        else:
            verdict = self.judge(twist)
        self._note(verdict)
        if verdict.scale >= 1.0 and verdict.turn >= 1.0:
            return twist
        s = verdict.scale
        return Twist(twist.vx * s, twist.vy * s, twist.wz * verdict.turn)

    def judge(self, twist: Twist) -> Verdict:
        """The verdict on ``twist`` against the current points (``filter`` without the scan)."""
        c = self.config
        speed = math.hypot(twist.vx, twist.vy)
        p = self.points
        if speed < MOVING:
            return self._judge_turn(twist.wz)
        ux, uy = twist.vx / speed, twist.vy / speed
        along = p[:, 0] * ux + p[:, 1] * uy
        across = np.abs(p[:, 1] * ux - p[:, 0] * uy)
        ahead = along > 0.0
        nearest = float(np.hypot(p[ahead, 0], p[ahead, 1]).min()) if ahead.any() else math.inf

        def in_box(zone) -> np.ndarray:
            return ahead & (along < zone.length) & (across < zone.half_width)

        # the stop box's points the outline would touch going straight until the chassis' leading
        # edge reaches the box's end: its corners, beside that sweep, are things the robot passes by
        boxed = p[in_box(c.stop)]
        if len(boxed) >= c.min_points:
            sweep = max(c.stop.length - (c.chassis[0] * abs(ux) + c.chassis[1] * abs(uy)), 0.0)
            steps = np.linspace(0.0, sweep, max(2, math.ceil(sweep / SWEEP_STEP) + 1))
            swept = self.outline.inside(boxed[None, :, 0] - steps[:, None] * ux, boxed[None, :, 1] - steps[:, None] * uy).any(axis=0)
            if np.count_nonzero(swept) >= c.min_points:
                return Verdict(STOP, 0.0, nearest, self._turn_scale(twist.wz))
        scale, action = 1.0, NONE
        if np.count_nonzero(in_box(c.slowdown)) >= c.min_points and speed > c.slowdown.speed:
            scale, action = c.slowdown.speed / speed, SLOWDOWN
        reach = self.outline.reach + speed * (c.approach.time_before_collision + c.approach.time_step)
        hit = self._time_to_collision(twist, p[np.einsum("ij,ij->i", p, p) < reach ** 2])
        if hit is not None and hit / c.approach.time_before_collision < scale:
            scale, action = hit / c.approach.time_before_collision, APPROACH
        return Verdict(action, scale, nearest, scale)

    def _judge_turn(self, wz: float) -> Verdict:
        """A turn on the spot: what the outline sweeps turning."""
        turn = self._turn_scale(wz)
        if turn >= 1.0:
            return CLEAR
        p = self.points
        nearest = float(np.sqrt(np.einsum("ij,ij->i", p, p).min()))
        return Verdict(STOP if turn <= 0.0 else APPROACH, 1.0, nearest, turn)

    def _turn_scale(self, wz: float) -> float:
        """The factor on ``wz`` that keeps the turning outline ``time_before_collision`` from
        contact: 0 when it touches within the first step."""
        if abs(wz) < TURNING:
            return 1.0
        p = self.points
        near = p[np.einsum("ij,ij->i", p, p) < self.outline.reach ** 2]
        hit = self._time_to_collision(Twist(0.0, 0.0, wz), near)
        if hit is None:
            return 1.0
        step = self.config.approach.time_step
        return 0.0 if hit <= step + 1e-9 else hit / self.config.approach.time_before_collision

    def _time_to_collision(self, twist: Twist, points: np.ndarray) -> float | None:
        """When the outline, carried along ``twist``, first touches ``min_points`` of ``points``
        (None: not within the horizon). Poses come from the exact integral of a constant body
        twist; the points are taken into the body frame of each pose."""
        if len(points) < self.config.min_points:
            return None
        t, w = self._times, twist.wz
        if abs(w) < 1e-6:
            cx, cy = twist.vx * t, twist.vy * t
        else:
            s, c1 = np.sin(w * t), 1.0 - np.cos(w * t)
            cx = (twist.vx * s - twist.vy * c1) / w
            cy = (twist.vy * s + twist.vx * c1) / w
        cos, sin = np.cos(w * t)[:, None], np.sin(w * t)[:, None]
        dx, dy = points[None, :, 0] - cx[:, None], points[None, :, 1] - cy[:, None]
        inside = self.outline.inside(cos * dx + sin * dy, cos * dy - sin * dx)
        touching = np.count_nonzero(inside, axis=1) >= self.config.min_points
        return float(t[np.argmax(touching)]) if touching.any() else None

    def _note(self, verdict: Verdict) -> None:
        """Log each change of action once: a stop (or going blind) as a warning, slowing and
        clearing at debug level (a patrol slows near things all day; the status bar and the
        report's encounters show it)."""
        if verdict.action != self.verdict.action:
            level = logging.WARNING if verdict.holding else logging.DEBUG
            self.log.log(level, "collision monitor: %s (scale %.2f, turn %.2f, nearest %.2f m)",
                         verdict.action, verdict.scale, verdict.turn, verdict.nearest)
        self.verdict = verdict

    def _note_fault(self, fault: str | None, now: float) -> None:
        """A blind lidar is a fault in the log (its end too, with how long it lasted); a stale
        one is the navigator's to report (it waits for scans), so it is logged at INFO here."""
        if self.fault == LIDAR_BLIND and self.untrusted_since is not None:
            self.log.warning("collision monitor: lidar_blind over after %.1f s", now - self.untrusted_since)
        if fault == LIDAR_BLIND:
            self.log.warning("collision monitor: lidar_blind (%s): linear motion stopped", self.blind_reason)
        elif fault == LIDAR_STALE:
            self.log.info("collision monitor: no scan for %.1f s: linear motion stopped", self.config.scan_timeout)
