"""Navigate-to-pose: the glue between costmaps, the NavFn planner, MPPI and the mux.

One goal at a time, driven entirely by three scheduled ticks (never blocking, never reading a
wall clock; ``now`` comes from the runtime's scheduler):

==================  =======  ==============================================================
tick                rate     what
==================  =======  ==============================================================
tick_local_costmap  5 Hz     local 3 x 3 m window from the latest scan (seed)
tick_planner        1 Hz     global costmap from the latest scan, then replan (Nav2's 1 Hz)
tick_control        20 Hz    goal check, blocked-path replan, MPPI -> smoother -> ``auto``
==================  =======  ==============================================================

Frames (REP-105): goals, plans and the global costmap live in ``map``; the local costmap and
MPPI in ``odom``, reached through the localisation's ``map -> odom``. Ground truth is never
an input.

Outcomes are ``succeeded``, ``failed(reason)`` (timeout, no path, no progress for 10 s as
Nav2's progress checker, no valid control after the bounded recoveries) or ``canceled``. A cancel, and an e-stop (which cancels the goal: the seed's
e-stop was decorative until it did), publishes a zero twist on ``auto`` at once, so the base
drives zero from its next tick; after a release nothing restarts by itself: whoever sent the
goal decides (ISO 13850 practice).

Recovery when MPPI finds no valid control (``nav.recovery``): clear the local costmap, back off
slowly away from the nearest obstacle for ``backoff_time``, reset the controller and retry, at
most ``max_recoveries`` times per goal.

People (issue 28 item 2: "the robot waits at a distance or goes round by another aisle; it does
not squeeze by"): the costmaps' person layer makes NavFn go round by another aisle where there
is one. Where there is none, the goal *waits* instead of failing or squeezing: zero twist, its
deadline and progress check stopped, replanning at 1 Hz, while a person stands in the only way
(no plan on the global costmap, but one on it with the people's bodies taken out:
``without_people``), on the goal itself (inside a person's keep-out), or so close that MPPI has
no valid control (recovery would back off into whoever is behind). Those waits and the
collision monitor's holds count together against ``blocked_wait``; past it the goal fails
``blocked`` and the patrol comes back to the pot after the others (a bounded wait, then retry).
A person's keep-out reaches along their next ``predict_time`` s of walking, and while the robot
stands inside it (a walker who does not yield is coming) it does not just stand there: it steps
out of the way (``nav.people_nearby``) to the nearest place out of everyone's way
(``nav.refuge``), never across a walker's way, and stands where there is none. While it waits for a person it keeps the wider ``wait_clearance`` (1 m) the same way: it
waits at a distance, and a grower who stopped for it gets room to come by; a grower the
collision monitor holds it for is stepped back from the same way, not pressed on. A robot in the
lane of someone walking its way (their next ``lane_time`` s) steps out while they are metres
off, faster than it may within 1 m of them. A robot inside someone's keep-out (a grower
who stopped for it at arm's length) plans its way out, never nearer anyone than it stands, and
takes it at 0.15 m/s where MPPI finds no control and no refuge is in reach: standing there, it
and the grower waited for each other. Within ``nav.waits.FINISH`` of its goal it finishes its
approach whoever is near, the people guard binding the last centimetres. A robot boxed in (every cell round it taken, the
planner's ``StartBlocked``: someone against it) waits ``blocked_wait`` like a hold instead of
failing goal after goal, and a failed plan is retried at most every ``BLOCKED_REPLAN_GAP``.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Callable, Optional, Protocol

import numpy as np

from hw.interfaces import ZERO_TWIST, LidarScan, Twist
from hw.odometry import Pose2D
from hw.people import PeopleSource, nobody
from nav.config import NavConfig
from nav.people_nearby import PeopleNearby
from nav.goal_state import State  # noqa: F401  (the goal's states, for callers too)
from nav.recovery import Recovery
from nav.waits import LANE, Waits  # noqa: F401  (LANE: the reason the goal holds, for callers)
from nav.way_out import WayOut
from nav.costmap.grid import INSCRIBED, UNKNOWN, CostGrid
from nav.frames import compose, distance, inverse, transform_path, transform_points
from nav.goal_checker import GoalChecker
from nav.localisation import Localisation
from nav.mppi.controller import NoValidControl
from nav.planner import PlanningError, StartBlocked
from nav.turning_places import close_turns
from nav.readiness import Readiness
from nav.smoother import VelocitySmoother

log = logging.getLogger(__name__)


#: Least time between two replans triggered by a blocked path or a failed plan (the 1 Hz replan still runs): a
#: plan the local costmap disagrees with is redone at once, but not on every 50 ms control tick.
BLOCKED_REPLAN_GAP = 0.5
#: Room the global costmap takes in round the robot and the goal before a plan, m: the planner's
#: 0.5 m goal tolerance and the robot's footprint fit inside it.
COVER_MARGIN = 1.0


class Costmap(Protocol):
    grid: CostGrid

    def update(self, scan: LidarScan, sensor_pose: tuple[float, float, float], robot_xy: tuple[float, float]) -> None: ...

    def clear(self) -> None: ...

    def cover(self, x0: float, y0: float, x1: float, y1: float) -> None: ...

    def without_people(self) -> CostGrid: ...


class Planner(Protocol):
    def plan(self, grid: CostGrid, start_xy, goal_xy) -> np.ndarray: ...


class Controller(Protocol):
    def compute(self, pose, velocity, path: np.ndarray, goal, grid: CostGrid) -> tuple[float, float, float]: ...

    def reset(self) -> None: ...


@dataclass(frozen=True)
class Feedback:
    state: State
    distance_remaining: float
    elapsed: float
    recoveries: int
    replans: int
    reason: str = ""


@dataclass
class Sources:
    """What the navigator reads from and writes to the robot (callbacks keep nav below mission)."""

    odom_pose: Callable[[], Pose2D]
    """``odom -> base_link`` from wheel odometry."""
    odom_twist: Callable[[], Twist]
    """The measured body twist."""
    scan: Callable[[], Optional[LidarScan]]
    """The latest lidar revolution, None during a dropout."""
    publish: Callable[[Twist, float], None]
    """Into the twist_mux's ``auto`` source: autonomy never bypasses the mux (seed)."""
    estop: Callable[[], bool]
    """True while the e-stop is engaged."""
    held: Callable[[], bool] = lambda: False
    """True while the collision monitor keeps the base from driving where it was told."""
    people: PeopleSource = nobody
    """The person tracker's people, ``odom`` frame (the costmaps' person layers read the same)."""
    escape: Callable[[float], Twist] = lambda speed: ZERO_TWIST
    """A step at this speed straight away from the people the guard holds the base from, base
    frame (``hw.people_guard.PeopleGuard.escape``); zero when there is none."""


class Navigator(Waits, WayOut, Recovery):
    def __init__(self, config: NavConfig, sources: Sources, localisation: Localisation,
                 local_costmap: Costmap, global_costmap: Costmap, planner: Planner, controller: Controller,
                 readiness: Readiness | None = None):
        self.config = config
        self.io = sources
        self.localisation = localisation
        self.local_costmap = local_costmap
        self.global_costmap = global_costmap
        self.planner = planner
        self.controller = controller
        self.readiness = readiness
        """The start-up cascade; goals are refused until it is active (None: always active)."""
        self.people = PeopleNearby(config, sources.people, lambda: self.localisation.map_to_odom())
        """Where people keep the robot out, map frame, and the step out of their way."""
        self.smoother = VelocitySmoother(config.smoother)
        self.goal_checker = GoalChecker(config.goal_checker)
        mx, my, myaw = config.navigator.lidar_mount
        self._lidar_mount = Pose2D(mx, my, myaw)
        self.state = State.IDLE
        self.reason = ""
        self.goal: Pose2D | None = None
        self.path: np.ndarray | None = None
        """The current global plan, (N, 2) map-frame points."""
        self._start = self._deadline = self._last_control = self._last_plan = self._last_attempt = 0.0
        self._recoveries = self._replans = self._plan_failures = 0
        self._backoff_until = 0.0
        self._backoff = ZERO_TWIST
        self._checkpoint: tuple[Pose2D, float] | None = None
        self.blind = False
        """True while a goal holds for want of a fresh scan (``scan_timeout``)."""
        self.held_for = 0.0
        """Seconds this goal has waited, held by the collision monitor or for a person in the
        way (``blocked_wait``)."""
        self._held_since: float | None = None
        """Since when the base has been held without a break (``nav.waits.ESCAPE_AFTER``)."""
        self._escape_until = -math.inf
        """Until when the robot steps straight away from the people holding it."""
        self.waiting_for = ""
        """Why the goal waits for people now ('' while it does not)."""
        self._person_blocks = self._start_blocked = False
        self._way_out_at: tuple[float, np.ndarray | None] = (-math.inf, None)
        """When ``_leave`` last planned its way out of a keep-out, and that way (None: none)."""
        self.keep_out: Callable[[CostGrid, tuple[float, float]], CostGrid] | None = None
        """Where a drive may not go now, as a filter of the global costmap's grid from where the
        robot stands (a fleet's aisles held by other robots, ``mission.patrol.aisle_gate``);
        None: anywhere the costmap allows."""

    # -- the goal API --------------------------------------------------------------------------

    @property
    def active(self) -> bool:
        return self.state in (State.FOLLOWING, State.RECOVERING)

    def navigate_to(self, goal: Pose2D, now: float, timeout: float | None = None,
                    xy_tolerance: float | None = None) -> None:
        """Start (or replace) a goal in the map frame; progress via ``feedback``. Before the
        readiness cascade is active the goal fails at once, with the stage that is missing.
        ``xy_tolerance`` tightens the goal checker's for this goal (a look that must frame a tag
        needs the robot there, not within the 0.25 m a patrol's approach allows)."""
        self.goal = goal
        self.state, self.reason = State.FOLLOWING, ""
        self._start, self._last_control = now, now
        self._deadline = now + (timeout if timeout is not None else self.config.navigator.default_timeout)
        self._recoveries = self._replans = self._plan_failures = 0
        self._checkpoint = None
        self.held_for = 0.0
        self._held_since, self._escape_until = None, -math.inf
        self.waiting_for, self._person_blocks, self._start_blocked = "", False, False
        self._last_attempt = -math.inf
        self.path = None
        self.goal_checker.reset(xy_tolerance)
        self.controller.reset()
        self.smoother.reset()
        if self.readiness is not None and not self.readiness.tick(now):
            self._finish(State.FAILED, f"navigation {self.readiness.status(now)}", now)
            return
        self._replan(now)

    def cancel(self, now: float, reason: str = "canceled") -> None:
        if self.active:
            self._finish(State.CANCELED, reason, now)

    def feedback(self, now: float) -> Feedback:
        return Feedback(self.state, self._remaining(), (now - self._start) if self.goal else 0.0,
                        self._recoveries, self._replans, self.reason)

    def map_pose(self) -> Pose2D:
        """The robot in the map frame: ``map -> odom`` composed with odometry."""
        return compose(self.localisation.map_to_odom(), self.io.odom_pose())

    # -- scheduled ticks -----------------------------------------------------------------------

    def tick_local_costmap(self, now: float) -> None:
        self._update(self.local_costmap, self.io.odom_pose())

    def tick_planner(self, now: float) -> None:
        self._update(self.global_costmap, self.map_pose())
        if self.state is State.FOLLOWING:
            self._replan(now)

    def tick_control(self, now: float) -> None:
        if not self.active:
            return
        if self.io.estop():
            self._finish(State.CANCELED, "e-stop engaged", now)
            return
        dt, self._last_control = now - self._last_control, now
        if self._blind(now):
            self._deadline += dt  # a pause, not time spent on the goal
            self._checkpoint = None
            self.io.publish(ZERO_TWIST, now)
            return
        if (self._waiting(now, dt) or self._boxed_in(now, dt) or self._out_of_a_lane(now, dt)
                or self._waiting_for_people(now, dt)):
            return
        if now >= self._deadline:
            self._finish(State.FAILED, f"timeout after {now - self._start:.1f} s", now)
            return
        pose = self.map_pose()
        if self.goal_checker.reached(pose, self.goal, self.io.odom_twist()):
            self._finish(State.SUCCEEDED, "", now)
            return
        if not self._progressing(pose, now):
            self._finish(State.FAILED, f"no progress: moved less than {self.config.navigator.progress_radius} m "
                         f"in {self.config.navigator.progress_time:g} s, {distance(pose, self.goal):.2f} m from the goal", now)
            return
        if self.state is State.RECOVERING:
            self._recover(now, dt)
            return
        if now - self._last_attempt >= BLOCKED_REPLAN_GAP and (self.path is None or self._path_blocked()):
            self._update(self.global_costmap, pose)
            if not self._replan(now) and not self._straight_in(pose):
                return
        if self.path is None:  # the last plan failed less than BLOCKED_REPLAN_GAP ago
            self.io.publish(ZERO_TWIST, now)
            return
        self._follow(pose, now, dt)

    # -- the pieces ----------------------------------------------------------------------------

    def _blind(self, now: float) -> bool:
        """No fresh lidar scan: hold still until scans return (logged once per gap)."""
        scan = self.io.scan()
        blind = scan is None or now - scan.stamp > self.config.navigator.scan_timeout
        if blind != self.blind:
            if blind:
                log.warning("no lidar scan for over %.1f s: holding the goal still until scans return",
                            self.config.navigator.scan_timeout)
            else:
                log.info("lidar scans back: following again")
            self.smoother.reset()
            self.blind = blind
        return blind

    def _hold(self, now: float, dt: float, why: str, wait: float | None = None) -> bool:
        """Count ``dt`` of waiting against ``wait`` (``blocked_wait`` when None) with the goal's
        clocks stopped; True when the wait ran out and the goal failed ``blocked``."""
        wait = self.config.navigator.blocked_wait if wait is None else wait
        if self.held_for == 0.0:
            log.info("%s: waiting up to %.0f s", why, wait)
        self.held_for += dt
        if self.held_for > wait:
            self._finish(State.FAILED, f"blocked: {why} for {wait:g} s", now)
            return True
        self._deadline += dt
        if self._checkpoint is not None:
            self._checkpoint = (self._checkpoint[0], self._checkpoint[1] + dt)
        return False

    def _progressing(self, pose: Pose2D, now: float) -> bool:
        """Nav2's SimpleProgressChecker: moving ``progress_radius`` from the last checkpoint
        renews it; failing to within ``progress_time`` is no progress (recoveries renew it)."""
        cfg = self.config.navigator
        if self._checkpoint is None or distance(pose, self._checkpoint[0]) >= cfg.progress_radius:
            self._checkpoint = (pose, now)
        return now - self._checkpoint[1] <= cfg.progress_time

    def _update(self, costmap: Costmap, base: Pose2D) -> None:
        scan = self.io.scan()
        if scan is None:
            return
        lidar = compose(base, self._lidar_mount)
        m = COVER_MARGIN
        costmap.cover(base.x - m, base.y - m, base.x + m, base.y + m)  # the global one must hold the robot
        costmap.update(scan, (lidar.x, lidar.y, lidar.yaw), (base.x, base.y))

    def _replan(self, now: float) -> bool:
        pose = self.map_pose()
        m = COVER_MARGIN
        self.global_costmap.cover(min(pose.x, self.goal.x) - m, min(pose.y, self.goal.y) - m,
                                  max(pose.x, self.goal.x) + m, max(pose.y, self.goal.y) + m)
        self._last_attempt = now
        try:
            grid = self.global_costmap.grid
            if self.keep_out is not None:
                grid = self.keep_out(grid, (pose.x, pose.y))
            self.path = self._plan_round_turns(grid, pose)
        except StartBlocked:
            self._start_blocked = not self._only_people_block(pose)
            self._person_blocks = not self._start_blocked
            self.io.publish(ZERO_TWIST, now)
            return False
        except PlanningError as exc:
            self._person_blocks = self._only_people_block(pose)
            if self._person_blocks:
                self.io.publish(ZERO_TWIST, now)
                return False  # a wait, not a failure (``_waiting_for_people``)
            self._plan_failures += 1
            log.info("planning failed (%d/%d): %s", self._plan_failures, self.config.navigator.max_plan_failures, exc)
            if self._plan_failures >= self.config.navigator.max_plan_failures:
                self._finish(State.FAILED, f"no path: {exc}", now)
            elif self.path is None:
                self.io.publish(ZERO_TWIST, now)  # nothing to follow yet: hold still
            return False
        self._plan_failures = 0
        self._person_blocks = self._start_blocked = False
        self._replans += 1
        self._last_plan = now
        return True

    def _plan_round_turns(self, grid: CostGrid, pose: Pose2D) -> np.ndarray:
        """The plan round the places where people who pace turn (``nav.turning_places``), else,
        with no way round, through them."""
        closed = close_turns(grid, self.people.turns_in_map(), self.people.robot_radius,
                             ((pose.x, pose.y), (self.goal.x, self.goal.y)))
        if closed is not None:
            try:
                return self._plan(closed, pose)
            except PlanningError:
                pass
        return self._plan(grid, pose)

    def _follow(self, pose: Pose2D, now: float, dt: float) -> None:
        odom_from_map = inverse(self.localisation.map_to_odom())
        path = transform_path(odom_from_map, self._pruned_path(pose))
        goal = compose(odom_from_map, self.goal)
        odom = self.io.odom_pose()
        tw = self.io.odom_twist()
        try:
            vx, vy, wz = self.controller.compute((odom.x, odom.y, odom.yaw), (tw.vx, tw.vy, tw.wz), path,
                                                 (goal.x, goal.y, goal.yaw), self.local_costmap.grid)
        except NoValidControl as exc:
            if self.io.held():  # someone close: wait for them, never back off into whoever is behind
                self.io.publish(ZERO_TWIST, now)
                return
            if self._person_close():  # a person's keep-out: out of their way, not a recovery
                if not self._hold(now, dt, "a person close by", self.config.navigator.person_wait):
                    step = self._evade()
                    self.io.publish(self._leave(pose, now) if step == ZERO_TWIST else step, now)
                return
            self._start_recovery(now, str(exc))
            return
        self.io.publish(self.smoother.smooth(Twist(vx, vy, wz), dt), now)

    def _pruned_path(self, pose: Pose2D) -> np.ndarray:
        """The plan from the point nearest the robot on, with headings: the tangent along the
        way and the goal's yaw at the end (Nav2 hands MPPI the plan pruned the same way)."""
        xy = self._ahead(pose)
        if len(xy) < 2:
            xy = np.vstack([[pose.x, pose.y], [self.goal.x, self.goal.y]])
        d = np.diff(xy, axis=0)
        yaw = np.empty(len(xy))
        yaw[:-1] = np.arctan2(d[:, 1], d[:, 0])
        yaw[-1] = self.goal.yaw
        return np.column_stack([xy, yaw])

    def _path_blocked(self) -> bool:
        """Does the plan cross a lethal or inscribed cell the local costmap sees now?"""
        grid = self.local_costmap.grid
        odom_from_map = inverse(self.localisation.map_to_odom())
        pts = transform_points(odom_from_map, self.path)
        cost = grid.cost_at(pts[:, 0], pts[:, 1], outside=0)
        return bool(np.any((cost >= INSCRIBED) & (cost != UNKNOWN)))

    def _remaining(self) -> float:
        if self.goal is None:
            return 0.0
        pose = self.map_pose()
        if self.path is None or len(self.path) < 2:
            return distance(pose, self.goal)
        xy = self._ahead(pose)
        return float(np.hypot(*np.diff(xy, axis=0).T).sum()) + math.hypot(xy[0, 0] - pose.x, xy[0, 1] - pose.y)

    def _ahead(self, pose: Pose2D) -> np.ndarray:
        """The plan from the point nearest the robot on."""
        start = int(np.argmin(np.hypot(self.path[:, 0] - pose.x, self.path[:, 1] - pose.y)))
        return self.path[start:]

    def _finish(self, state: State, reason: str, now: float) -> None:
        self.state, self.reason = state, reason
        self.smoother.reset()
        self.io.publish(ZERO_TWIST, now)
        log.info("navigation %s%s after %.1f s", state.value, f" ({reason})" if reason else "", now - self._start)

