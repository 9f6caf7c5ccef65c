"""What a patrol shows in Foxglove: the channels, what goes on each, and at what beat.

One :class:`PatrolChannels` is built from the running parts (``robot``, ``nav``, and the patrol
``tree`` when there is one) on a private ``foxglove.Context``; sinks attach to that context: an
MCAP file (``mission.record.mcap_file``) or the WebSocket server (``mission.record.live``), or
both, and see the same channels. Nothing here knows which sinks are listening.

========================  ========================  =====  ====================================
topic                     schema                    rate   what
========================  ========================  =====  ====================================
/tf                       foxglove.FrameTransforms  10 Hz  map->odom (localisation), odom->
                                                           base_link (wheel odometry), base_link
                                                           to lidar, front_camera_optical and
                                                           wrist_camera_optical (arm FK)
/scan                     foxglove.LaserScan        10 Hz  each new revolution, frame ``lidar``
/camera/front/compressed  foxglove.CompressedImage  new    each frame its pipeline captured,
/camera/wrist/compressed  foxglove.CompressedImage  new    as JPEG (polled at 10 Hz; the caps
                                                           are 2 Hz; never triggers a capture)
/plan                     foxglove.PosesInFrame     2 Hz   the navigator's global plan, ``map``
/path                     foxglove.PosesInFrame     2 Hz   the driven path (map pose every 5 cm)
/costmap/global           foxglove.Grid             1 Hz   Nav2 costs, uint8 field ``cost``
/map                      foxglove.Grid             1 Hz   SLAM's map, int8 field ``occupancy``
/pots                     foxglove.SceneUpdate      1 Hz   a cylinder and a label per pot,
                                                           coloured by status
/people                   foxglove.SceneUpdate      10 Hz  the tracked people, ``odom``: body,
                                                           velocity arrow, id / speed /
                                                           confidence (label and metadata;
                                                           ``mission.record.people_scene``),
                                                           only while anyone is tracked
/mission/state            JSON (jsonschema)         1 Hz   tree text, current step, pots done,
                                                           pot statuses, notes, outcome
/mission/log              foxglove.Log              new    pots recorded, anomalies, notes,
                                                           e-stop events, the outcome
========================  ========================  =====  ====================================

Everything runs in one scheduler task at the lidar's 10 Hz, on the lidar's beat (so reading
the scan never makes the sim cast a revolution at another instant than navigation would: a
recorded run is the run it would have been, which the tests check); the slower channels take
turns on their own beats of it (plan/path on tick 2 of every 5, costmap/map on 4 of 10,
pots/state/log on 7 of 10), so no tick carries all the work. Timestamps, message and log time
alike, are the runtime clock's (sim time in the sim) in nanoseconds; never the wall.

Logging runs in the control loop's thread, so it only reads (no capture, no request, no wait),
builds nothing for a channel no sink listens to, and never raises: a beat that fails is logged
once, counted in ``errors`` and tried again next time; the other beats go on.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Callable, Protocol

import foxglove
import numpy as np
from foxglove.channels import (CompressedImageChannel, FrameTransformsChannel, GridChannel, LaserScanChannel,
                               LogChannel, PosesInFrameChannel, SceneUpdateChannel)
from foxglove.messages import (Color, CompressedImage, CylinderPrimitive, FrameTransforms, KeyValuePair, LaserScan,
                               Log, LogLevel, PackedElementFieldNumericType, Pose, PosesInFrame, SceneEntity,
                               SceneUpdate, TextPrimitive, Timestamp, Vector3)

from arm.kinematics import camera_ray
from mission.record.messages import (grid_message, ns, optical_rotation, planar, point_pose, quaternion, stamp,
                                     transform, uniform_scan)
from mission.record.people_scene import people_update
from hw.odometry import Pose2D
from mission.runtime.robot import Robot
from nav.navigator import Navigator

log = logging.getLogger(__name__)

RATE = 10.0
"""The task's rate, Hz: the lidar's (and ``map -> odom``'s) 10 Hz."""
PLAN_BEAT = (5, 2)
"""(every n ticks, on tick k): plan and driven path at 2 Hz."""
GRID_BEAT = (10, 4)
"""Global costmap and SLAM map at 1 Hz."""
STATE_BEAT = (10, 7)
"""Pots scene, mission state and its log at 1 Hz."""
TRAIL_STEP = 0.05
"""The driven path gains a point each time the map pose moved this far, m (a patrol of ~50 m
is ~1000 points)."""
LIDAR_HEIGHT = 0.159
"""Lidar optical centre above base_link, m (the sim model: post at 0.084 + site at 0.075);
display only, nothing measures with it."""
FRONT_OPTICAL = (-0.5, 0.5, -0.5, 0.5)
"""base_link -> an optical frame looking along +x (x right, y down, z forward), as (x, y, z, w)."""

STATUS_COLOURS = {
    "pending": (0.6, 0.6, 0.6, 0.8),
    "active": (0.2, 0.5, 1.0, 1.0),
    "inspected": (0.1, 0.8, 0.2, 1.0),
    "anomaly": (1.0, 0.6, 0.0, 1.0),
    "failed": (0.9, 0.1, 0.1, 1.0),
    "skipped": (0.3, 0.3, 0.3, 0.8),
}
"""Pot colours by status; ``anomaly`` is an inspected pot with an anomaly (spec/report.md)."""

STATE_SCHEMA = {
    "type": "object",
    "title": "lupin.MissionState",
    "properties": {
        "t": {"type": "number", "description": "runtime seconds since the mission started"},
        "step": {"type": "string", "description": "the running leaf (or the hold's reason)"},
        "pots_done": {"type": "integer"},
        "pots_total": {"type": "integer"},
        "pots": {"type": "object", "additionalProperties": {"type": "string"},
                 "description": "pot id -> pending | active | inspected | anomaly | failed | skipped"},
        "outcome": {"type": ["string", "null"]},
        "notes": {"type": "object", "additionalProperties": {"type": "string"}},
        "tree": {"type": "string", "description": "the tree with its statuses (py_trees unicode)"},
    },
    "required": ["t", "step", "pots_done", "pots_total", "pots", "outcome", "tree"],
}

TOPICS = {
    "tf": "/tf", "scan": "/scan", "plan": "/plan", "path": "/path", "costmap": "/costmap/global",
    "map": "/map", "pots": "/pots", "people": "/people", "state": "/mission/state", "log": "/mission/log",
    "front": "/camera/front/compressed", "wrist": "/camera/wrist/compressed",
}


class Parts(Protocol):
    """What the channels read: a ``PatrolRun`` is one; ``tree`` may be None (no mission)."""

    robot: Robot
    nav: Navigator
    tree: object


@dataclass
class _Beat:
    name: str
    every: int
    phase: int
    fn: Callable[[float], None]


class PatrolChannels:
    """The patrol's Foxglove channels on a private context; ``start()`` schedules them."""

    def __init__(self, robot: Robot, nav: Navigator, tree=None, *, context: foxglove.Context | None = None,
                 task: str = "foxglove"):
        self.robot, self.nav, self.tree = robot, nav, tree
        self.context = context or foxglove.Context()
        self.task = task
        c = self.context
        self.tf = FrameTransformsChannel(TOPICS["tf"], context=c)
        self.scan = LaserScanChannel(TOPICS["scan"], context=c)
        self.plan = PosesInFrameChannel(TOPICS["plan"], context=c)
        self.path = PosesInFrameChannel(TOPICS["path"], context=c)
        self.costmap = GridChannel(TOPICS["costmap"], context=c)
        self.map = GridChannel(TOPICS["map"], context=c)
        self.cameras = {name: CompressedImageChannel(TOPICS[name], context=c) for name in ("front", "wrist")}
        self.pots = SceneUpdateChannel(TOPICS["pots"], context=c)
        self.people = SceneUpdateChannel(TOPICS["people"], context=c)
        self.state = foxglove.Channel(TOPICS["state"], schema=STATE_SCHEMA, context=c)
        self.log = LogChannel(TOPICS["log"], context=c)
        self.beats = [
            _Beat("trail", 1, 0, self._trail_point),
            _Beat("tf", 1, 0, self._transforms),
            _Beat("scan", 1, 0, self._scan),
            _Beat("cameras", 1, 0, self._frames),
            _Beat("people", 1, 0, self._people),
            _Beat("paths", *PLAN_BEAT, self._paths),
            _Beat("grids", *GRID_BEAT, self._grids),
            _Beat("mission", *STATE_BEAT, self._mission),
        ]
        self.errors: dict[str, int] = {}
        """Beat name -> how many of its ticks failed (the first one is logged)."""
        self.ticks = 0
        self._started = False
        self._last_scan: float | None = None
        self._last_frames: dict[str, object] = {}
        self._trail: list[Pose] = []
        self._trail_xy: tuple[float, float] | None = None
        self._tracked = False
        """The last people update had someone in it (so an empty one is owed when they go)."""
        self._logged: dict[str, int] = {"pots": 0, "anomalies": 0, "estop": 0}
        self._notes: set[str] = set()
        self._outcome_logged = False
        cfg = robot.config
        self._lidar = Pose2D(*cfg.nav.navigator.lidar_mount)
        self._front = cfg.patrol.front_camera_mount
        self._kinematics = cfg.arm.kinematics
        geometry = cfg.sim.geometry
        self._pot_size = (2 * geometry.pot_radius, geometry.pot_height)

    def follow(self, tree) -> None:
        """Show another patrol (``lupin serve`` starts and ends them), or none: its pots, state
        and news from its own start."""
        self.tree = tree
        self._logged = {"pots": 0, "anomalies": 0, "estop": 0}
        self._notes = set()
        self._outcome_logged = False

    @classmethod
    def of(cls, parts: Parts, **kw) -> "PatrolChannels":
        return cls(parts.robot, parts.nav, getattr(parts, "tree", None), **kw)

    # --- scheduling ---------------------------------------------------------------------
    def start(self) -> "PatrolChannels":
        """Schedule the task on the robot's scheduler, first tick on the lidar's next beat
        (idempotent: two sinks share one task)."""
        if not self._started:
            sched = self.robot.scheduler
            period = ns(1.0 / RATE)
            now = ns(sched.clock.now())
            first = -(-now // period) * period
            sched.every(self.task, RATE, self.tick, offset=(first - now) / 1e9)
            self._started = True
        return self

    def stop(self) -> None:
        if self._started:
            self.robot.scheduler.cancel(self.task)
            self._started = False

    def tick(self, now: float) -> None:
        for beat in self.beats:
            if self.ticks % beat.every == beat.phase:
                self._guarded(beat.name, beat.fn, now)
        self.ticks += 1

    def flush(self, now: float | None = None) -> None:
        """Everything once more as it stands (the end of a run: the final map, the pots' last
        colours, the outcome), whatever the beat."""
        now = self.robot.scheduler.clock.now() if now is None else now
        for beat in self.beats:
            self._guarded(beat.name, beat.fn, now)

    def close(self) -> None:
        """Stop the task and unadvertise every channel."""
        self.stop()
        for ch in (self.tf, self.scan, self.plan, self.path, self.costmap, self.map, *self.cameras.values(),
                   self.pots, self.people, self.state, self.log):
            ch.close()

    def _guarded(self, name: str, fn: Callable[[float], None], now: float) -> None:
        try:
            fn(now)
        except Exception:  # a viewer must never stop the robot: log once, count, go on
            n = self.errors.get(name, 0)
            self.errors[name] = n + 1
            if n == 0:
                log.exception("foxglove channels: %r failed at t=%.2f (logged once; counted in errors)", name, now)

    # --- 10 Hz: driven path, transforms, scan, camera frames ----------------------------------
    def _trail_point(self, now: float) -> None:
        pose = self.nav.map_pose()
        if self._trail_xy is None or math.hypot(pose.x - self._trail_xy[0], pose.y - self._trail_xy[1]) >= TRAIL_STEP:
            self._trail.append(point_pose(pose.x, pose.y, yaw=pose.yaw))
            self._trail_xy = (pose.x, pose.y)

    def _transforms(self, now: float) -> None:
        if not self.tf.has_sinks():
            return
        t, nav, robot = stamp(now), self.nav, self.robot
        map_odom, odom_base = nav.localisation.map_to_odom(), robot.base.odometry.pose
        tfs = [planar(t, "map", "odom", map_odom), planar(t, "odom", "base_link", odom_base),
               planar(t, "base_link", "lidar", self._lidar, LIDAR_HEIGHT),
               transform(t, "base_link", "front_camera_optical", *self._front, quaternion(FRONT_OPTICAL))]
        q = robot.arm.joint_vector()
        if q is not None:
            origin, axis = camera_ray(q, self._kinematics)
            tfs.append(transform(t, "base_link", "wrist_camera_optical", *map(float, origin),
                                 quaternion(optical_rotation(axis, float(q[0])))))
        self.tf.log(FrameTransforms(transforms=tfs), log_time=ns(now))

    def _scan(self, now: float) -> None:
        if not self.scan.has_sinks():
            return
        scan = self.robot.hal.lidar.latest_scan()
        if scan is not None and scan.stamp != self._last_scan:
            self._last_scan = scan.stamp
            start, end, ranges = uniform_scan(scan)
            self.scan.log(LaserScan(timestamp=stamp(scan.stamp), frame_id="lidar", pose=point_pose(0, 0),
                                    start_angle=start, end_angle=end, ranges=ranges.tolist(), intensities=[]),
                          log_time=ns(now))

    def _frames(self, now: float) -> None:
        for name, pipeline in (getattr(self.tree, "cameras", None) or {}).items():
            frame = pipeline.last
            if (name in self.cameras and frame is not None and frame is not self._last_frames.get(name)
                    and self.cameras[name].has_sinks()):
                self._last_frames[name] = frame
                self.cameras[name].log(CompressedImage(timestamp=stamp(frame.stamp), frame_id=f"{name}_camera_optical",
                                                       data=frame.jpeg, format="jpeg"), log_time=ns(now))

    def _people(self, now: float) -> None:
        """The tracker's people (``robot.people``: None when no tracker runs), while anyone is
        tracked and once more, empty, when the last one is gone."""
        people = getattr(self.robot, "people", None)
        if people is None or not self.people.has_sinks():
            return
        tracks = tuple(people.current())
        if tracks or self._tracked:
            walked = {p.id for p in people.confident()} if tracks else set()
            self.people.log(people_update(stamp(now), tracks, walked), log_time=ns(now))
        self._tracked = bool(tracks)

    # --- 2 Hz: plan and driven path -------------------------------------------------------
    def _paths(self, now: float) -> None:
        t, log_time = stamp(now), ns(now)
        if self.plan.has_sinks():
            plan = self.nav.path
            poses = [] if plan is None else [point_pose(x, y) for x, y in np.asarray(plan, dtype=float).reshape(-1, 2)]
            self.plan.log(PosesInFrame(timestamp=t, frame_id="map", poses=poses), log_time=log_time)
        if self.path.has_sinks():
            self.path.log(PosesInFrame(timestamp=t, frame_id="map", poses=self._trail), log_time=log_time)

    # --- 1 Hz: costmap and map --------------------------------------------------------------
    def _grids(self, now: float) -> None:
        t, log_time = stamp(now), ns(now)
        if self.costmap.has_sinks():
            g = self.nav.global_costmap.grid
            self.costmap.log(grid_message(t, "map", g.data, g.resolution, g.origin_x, g.origin_y, "cost",
                                          PackedElementFieldNumericType.Uint8), log_time=log_time)
        m = getattr(self.nav.localisation, "occupancy", None)
        if m is not None and self.map.has_sinks():
            self.map.log(grid_message(t, "map", m.occupancy, m.resolution, m.origin_x, m.origin_y, "occupancy",
                                      PackedElementFieldNumericType.Int8), log_time=log_time)

    # --- 1 Hz: pots, mission state, log ------------------------------------------------------
    def _mission(self, now: float) -> None:
        tree = self.tree
        if tree is None:
            return
        t, log_time = stamp(now), ns(now)
        report = tree.report
        statuses = pot_statuses(tree)
        if self.pots.has_sinks():
            self.pots.log(self._scene(t, tree, statuses), log_time=log_time)
        if self.state.has_sinks():
            self.state.log({
                "t": round(now - report.t0, 3), "step": tree.current_step(), "pots_done": tree.pots_done(),
                "pots_total": len(tree.mission.pots), "pots": statuses, "outcome": report.outcome,
                "notes": dict(tree.notes), "tree": tree.render(),
            }, log_time=log_time)
        for level, text in self._news(tree, report):
            self.log.log(Log(timestamp=t, level=level, message=text, name="lupin.patrol", file="", line=0),
                         log_time=log_time)

    def _scene(self, t: Timestamp, tree, statuses: dict[str, str]) -> SceneUpdate:
        """A cylinder per pot coloured by its status, labelled with its id, status and flower."""
        report = tree.report
        w, h = self._pot_size
        entities = []
        for pot in tree.mission.pots:
            status = statuses[pot.id]
            r, g, b, a = STATUS_COLOURS[status]
            colour = Color(r=r, g=g, b=b, a=a)
            entry = report.pots.get(pot.id, {})
            flower = (entry.get("flower") or {}).get("color", "")
            label = " ".join(s for s in (pot.id, status, flower) if s)
            entities.append(SceneEntity(
                timestamp=t, frame_id="map", id=pot.id, frame_locked=True,
                metadata=[KeyValuePair(key="status", value=status)],
                cylinders=[CylinderPrimitive(pose=point_pose(pot.x, pot.y, h / 2), size=Vector3(x=w, y=w, z=h),
                                             bottom_scale=1.0, top_scale=1.0, color=colour)],
                texts=[TextPrimitive(pose=point_pose(pot.x, pot.y, h + 0.15), billboard=True, font_size=14.0,
                                     scale_invariant=True, color=colour, text=label)]))
        return SceneUpdate(entities=entities)

    def _news(self, tree, report) -> list[tuple[LogLevel, str]]:
        """What happened since the last beat, once each: pots recorded, anomalies, notes,
        e-stop events, the outcome."""
        out = []
        pots = list(report.pots.values())
        for entry in pots[self._logged["pots"]:]:
            out.append((LogLevel.Info, f"{entry['id']} {entry['status']} (attempts {entry['attempts']}, "
                                       f"tag {entry['tag_read']}, flower {(entry.get('flower') or {}).get('color')})"))
        for a in report.anomalies[self._logged["anomalies"]:]:
            out.append((LogLevel.Warning, f"anomaly {a['kind']} at {a['pot']}: {a['detail']}"))
        for e in report.estop_events[self._logged["estop"]:]:
            out.append((LogLevel.Warning, f"e-stop {'engaged' if e.get('engaged') else 'released'} "  # the entry is stamped
                                          f"{e.get('t')} s into the patrol"))  # on the runtime clock: say which t this is
        self._logged = {"pots": len(pots), "anomalies": len(report.anomalies), "estop": len(report.estop_events)}
        for key in sorted(set(tree.notes) - self._notes):
            out.append((LogLevel.Warning, f"note {key}: {tree.notes[key]}"))
            self._notes.add(key)
        if report.outcome is not None and not self._outcome_logged:
            self._outcome_logged = True
            level = LogLevel.Info if report.outcome == "completed" else LogLevel.Error
            out.append((level, f"outcome {report.outcome}"))
        return out


def pot_statuses(tree) -> dict[str, str]:
    """pending | active | inspected | anomaly | failed | skipped for every pot of the mission."""
    report = tree.report
    flagged = {a["pot"] for a in report.anomalies}
    out = {}
    for pot in tree.mission.pots:
        entry, visit = report.pots.get(pot.id), tree.visits.get(pot.id)
        if entry is not None:
            status = entry["status"]
            out[pot.id] = "anomaly" if status == "inspected" and pot.id in flagged else status
        elif report.outcome is not None:
            out[pot.id] = "skipped"
        elif visit is not None and visit.attempts > 0:
            out[pot.id] = "active"
        else:
            out[pot.id] = "pending"
    return out
