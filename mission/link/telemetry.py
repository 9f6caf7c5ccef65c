"""Telemetry: what the runtime tells every client, topic by topic, at three beats.

=========  =========  ==========================================================================
topic      beat       content
=========  =========  ==========================================================================
state      fast 10Hz  pose (map), velocity, active mux source, e-stop (engaged, latched), battery,
                      and ``people`` while the tracker follows anyone (``PERSON_FIELDS``, map
                      frame; the key is left out when nobody is tracked)
nav        slow 2Hz   navigation state and reason, goal, the plan (every 4th point)
mission    slow 2Hz   mission state, name, current step, pots done / total, outcome, and the
                      energy budget's charge, charge expected at the dock and why it heads home
tree       slow 2Hz   py_trees' unicode tree with statuses, zlib'd UTF-8, when it changed (and
                      every 10th beat, for late joiners)
pots       slow 2Hz   each pot: position, status, tag read, flower, anomalies
status     slow 2Hz   controller states
scan       slow 2Hz   the lidar scan as map-frame points (every 2nd beam, float16)
map        map 1Hz    SLAM's occupancy grid, as deltas (``mission.link.wire``)
costmap    map 1Hz    the inflated global costmap scaled to 0..100, as deltas
log        as logged  every log record that passes the loggers' levels (INFO and up under
                      ``lupin serve``), one line each
=========  =========  ==========================================================================

The control thread only gathers numbers (cheap reads, copies of small arrays) and hands a
closure to the outbox; JSON, zlib and the network happen on the sender thread.
"""
from __future__ import annotations

import contextvars
import logging
import math
import zlib

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person
from mission.link.outbox import Outbox
from mission.link.wire import Grid, GridSender, dumps, tel_key
from nav.frames import transform_points

TREE_KEYFRAME = 10
"""The tree text is sent when it changes and every 10th slow beat (5 s) for late joiners."""
PERSON_FIELDS = ("id", "x", "y", "vx", "vy", "radius", "confidence", "walked")
"""One person on the wire, a list in this order: id, position (m) and velocity (m/s) in the map
frame to the centimetre, body radius (m), the tracker's confidence (0..1, two decimals), and 1 if
the distance rules act on them (they have walked, ``mission.runtime.people``), else 0. A list,
not an object: about 40 bytes a person at 10 Hz, and nothing when nobody is there."""
TOPICS = ("state", "nav", "mission", "tree", "pots", "status", "scan", "map", "costmap", "log")


def _r(v: float, nd: int = 3) -> float | None:
    return round(float(v), nd) if math.isfinite(v) else None


def _share(v: float | None) -> float | None:
    return None if v is None else _r(v)


class Telemetry:
    def __init__(self, service, outbox: Outbox, robot_name: str):
        self.service, self.outbox, self.robot_name = service, outbox, robot_name
        self._map, self._costmap = GridSender(), GridSender()
        self._tree_text = ""
        self._beats = 0

    def _post(self, topic: str, payload) -> None:
        self.outbox.post(tel_key(self.robot_name, topic), payload)

    # --- the three beats ---------------------------------------------------------------------
    def fast(self, now: float) -> None:
        s = self.service
        robot, pose, tw = s.robot, s.nav.map_pose(), s.robot.base.odometry.twist
        power = robot.power
        volts = power.reading.voltage if power.reading is not None else float("nan")
        amps = power.reading.current if power.reading is not None else float("nan")
        msg = {"t": round(now, 3), "pose": [_r(pose.x), _r(pose.y), _r(pose.yaw)],
               "velocity": [_r(tw.vx), _r(tw.vy), _r(tw.wz)], "mux": robot.base.source,
               "monitor": {"action": robot.monitor.verdict.action, "nearest": _r(robot.monitor.verdict.nearest),
                           "fault": robot.monitor.fault, "enabled": robot.monitor.config.enabled},
               "estop": {"engaged": robot.estop.engaged(),
                         "latched": bool(s.run is not None and s.run.tree.holds.latched),
                         "why": robot.estop.held_since_start},
               "battery": {"voltage": _r(volts, 2), "current": _r(amps, 2), "percentage": _r(power.state.percentage, 1),
                           "low": power.state.low}}
        people = people_rows(robot.people, s.nav.localisation.map_to_odom)
        if people:
            msg["people"] = people
        self._post("state", lambda: dumps(msg))

    def slow(self, now: float) -> None:
        s = self.service
        nav = s.nav
        plan = nav.path[::4] if nav.path is not None else np.zeros((0, 2))
        goal = [_r(nav.goal.x), _r(nav.goal.y), _r(nav.goal.yaw)] if nav.goal is not None and nav.active else None
        nav_msg = {"state": nav.state.value, "reason": nav.reason, "goal": goal,
                   "plan": np.round(plan, 3).tolist(), "blind": nav.blind}
        self._post("nav", lambda: dumps(nav_msg))
        self._post("status", lambda m={n: st.value for n, st in s.robot.controllers.states().items()}: dumps({"controllers": m}))
        self._mission()
        self._scan()

    def maps(self, now: float) -> None:
        s = self.service
        occ = getattr(s.nav.localisation, "occupancy", None)
        if occ is not None:
            grid = Grid(occ.occupancy, occ.resolution, occ.origin_x, occ.origin_y)
            self._post("map", lambda g=grid: self._map.encode(g))
        cg = s.nav.global_costmap.grid
        scaled = np.where(cg.data == 255, -1, np.minimum(cg.data, 254).astype(np.int16) * 100 // 254).astype(np.int8)
        self._post("costmap", lambda g=Grid(scaled, cg.resolution, cg.origin_x, cg.origin_y): self._costmap.encode(g))

    # --- pieces --------------------------------------------------------------------------------
    def _mission(self) -> None:
        s, run = self.service, self.service.run
        if run is None:
            msg = {"state": "idle" if not s.outcome else "done", "name": "", "step": "", "pots_done": 0,
                   "pots_total": 0, "outcome": s.outcome}
            self._post("mission", lambda: dumps(msg))  # the last patrol's pots stay on the clients' screens
            return
        tree, holds = run.tree, run.tree.holds
        state = "estop" if holds.latched else "paused" if holds.paused else "running"
        e = tree.energy
        msg = {"state": state, "name": tree.mission.name, "step": tree.current_step(), "pots_done": tree.pots_done(),
               "pots_total": len(tree.mission.pots), "outcome": "",
               "energy": {"charge": _share(e.charge), "at_dock": _share(e.projected), "why_home": e.why_home}}
        self._post("mission", lambda: dumps(msg))
        text = tree.render()
        self._beats += 1
        if text != self._tree_text or self._beats % TREE_KEYFRAME == 0:
            self._post("tree", lambda: zlib.compress(text.encode(), 6))
        self._tree_text = text
        current = tree.current_step()
        pots = []
        for p in tree.mission.pots:
            entry = run.report.pots.get(p.id)
            status = entry["status"] if entry else ("active" if current.endswith(f" {p.id}") else "pending")
            flower = (entry or {}).get("flower") or {}
            pots.append({"id": p.id, "x": p.x, "y": p.y, "status": status, "tag": (entry or {}).get("tag_read"),
                         "flower": flower.get("color"), "blooms": flower.get("blooms", 0),
                         "anomalies": [a["kind"] for a in run.report.anomalies if a["pot"] == p.id]})
        self._post("pots", lambda: dumps({"pots": pots}))

    def _scan(self) -> None:
        s = self.service
        scan = s.robot.hal.lidar.latest_scan()
        if scan is None:
            return
        pose = s.nav.map_pose()
        mx, my, myaw = s.config.nav.navigator.lidar_mount
        c, si = math.cos(pose.yaw), math.sin(pose.yaw)
        lx, ly = pose.x + c * mx - si * my, pose.y + si * mx + c * my
        r, a = scan.ranges[::2], scan.angles[::2] + (pose.yaw + myaw)
        ok = np.isfinite(r)
        pts = np.stack([lx + r[ok] * np.cos(a[ok]), ly + r[ok] * np.sin(a[ok])], axis=1).astype(np.float16)
        self._post("scan", lambda: pts.tobytes())


def people_rows(people, map_to_odom) -> list[list]:
    """The tracks of ``people`` (``robot.people``: None when no tracker runs) as
    ``PERSON_FIELDS`` rows in the map frame: the tracker works in odom (smooth for the costmaps),
    the console draws on SLAM's map, so each position goes through ``map -> odom`` and each
    velocity through its rotation, as the robot's pose does."""
    if people is None:
        return []
    tracks: list[Person] = list(people.current())
    if not tracks:
        return []
    walked = {p.id for p in people.confident()}
    t: Pose2D = map_to_odom()
    xy = transform_points(t, [(p.x, p.y) for p in tracks])
    v = transform_points(Pose2D(0.0, 0.0, t.yaw), [(p.vx, p.vy) for p in tracks])
    return [[p.id, _r(x, 2), _r(y, 2), _r(vx, 2), _r(vy, 2), _r(p.radius, 2), _r(p.confidence, 2), int(p.id in walked)]
            for p, (x, y), (vx, vy) in zip(tracks, xy, v)]


LOGGING_ROBOT: contextvars.ContextVar[str | None] = contextvars.ContextVar("lupin_logging_robot", default=None)
"""The robot whose runtime is running now, where several share a process (``lupin fleet sim``
sets it around each runtime's step): its log records are its own link's alone. None: one
robot in the process, or a record from no runtime's step; every link posts it."""


class LinkLogHandler(logging.Handler):
    """Log records, posted as ``log`` lines (never blocks; drops with the outbox when full)."""

    def __init__(self, outbox: Outbox, robot_name: str, now):
        super().__init__(logging.INFO)
        self.outbox, self.key, self.now, self.robot = outbox, tel_key(robot_name, "log"), now, robot_name

    def emit(self, record: logging.LogRecord) -> None:
        if LOGGING_ROBOT.get() not in (None, self.robot):
            return  # another robot's runtime logged it
        try:
            line = f"{self.now():8.1f} {record.levelname[0]} {record.getMessage()}"
        except Exception:  # a broken log call must not break the robot
            return
        self.outbox.post(self.key, lambda: line.encode())
