"""Moved pots judged on the world file: which pots the world moved, which a patrol reported
``moved``, and how far a mission's pots stand from the world's.

The world file is the only truth (issue 29 item 5): a pot the world did not move is unmoved,
however far the robot's map has drifted from the mission's frame (on the 36 m two-bay greenhouse
the drift alone once made 143 to 164 of 180 unmoved pots ``moved``, ``mission.patrol.map_drift``).
Poses are compared in the mission's frame the world gives (``mission_from_world``: the dock at
the origin), the frame of the report's drift-corrected ``moved`` poses and of the pots
``mission update`` writes.
"""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D
from mission.patrol.mission_file import Mission
from nav.frames import compose, inverse
from sim.world import World


def true_poses(world: World) -> dict[str, Pose2D]:
    """The world's pots by id, in the mission's frame the world gives (the dock at the origin)."""
    dock = inverse(Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw))
    return {p.id: compose(dock, Pose2D(p.x, p.y, p.facing)) for p in world.pots}


def shifted(before: World, after: World) -> set[str]:
    """Pots ``after`` has somewhere else or turned than ``before`` has them: the pots that moved."""
    was = {p.id: (p.x, p.y, p.facing) for p in before.pots}
    return {p.id for p in after.pots if was.get(p.id) != (p.x, p.y, p.facing)}


def reported_moved(doc: dict) -> dict[str, tuple[float, float]]:
    """The pots a patrol report (spec/report.md) says ``moved``, at the measured position."""
    return {a["pot"]: (float(a["x"]), float(a["y"])) for a in doc["anomalies"] if a["kind"] == "moved"}


def judge_report(doc: dict, world: World, moved: set[str]) -> dict:
    """A report's ``moved`` anomalies against ``moved``, the pots truly off the mission: how
    many it reported, how many of those were not moved (false; goal 0), the moved pots it did
    not report (missed), and each reported moved pot's distance from where ``world`` has it."""
    said, truth = reported_moved(doc), true_poses(world)
    hits = sorted(said.keys() & moved)
    return {"reported": len(said), "false": sorted(said.keys() - moved), "missed": sorted(moved - said.keys()),
            "errors": [math.hypot(said[i][0] - truth[i].x, said[i][1] - truth[i].y) for i in hits]}


def mission_offsets(mission: Mission, world: World) -> dict[str, tuple[float, float]]:
    """Each mission pot's distance (m) and turn (rad) from the world's pot of the same id."""
    truth = true_poses(world)
    pots = [p for p in mission.pots if p.id in truth]
    if not pots:
        return {}
    have = np.array([(p.x, p.y, p.facing) for p in pots])
    want = np.array([(truth[p.id].x, truth[p.id].y, truth[p.id].yaw) for p in pots])
    xy = np.hypot(*(have[:, :2] - want[:, :2]).T)
    turn = np.abs(np.remainder(have[:, 2] - want[:, 2] + math.pi, 2 * math.pi) - math.pi)
    return {p.id: (float(d), float(t)) for p, d, t in zip(pots, xy, turn)}


def off_pots(mission: Mission, world: World, xy: float, yaw: float) -> set[str]:
    """Mission pots farther than ``xy`` or turned more than ``yaw`` from the world's: the pots a
    patrol of ``mission`` in ``world`` ought to report ``moved`` (the patrol's own thresholds,
    ``moved_xy`` and ``moved_yaw``)."""
    return {pid for pid, (d, t) in mission_offsets(mission, world).items() if d > xy or t > yaw}
