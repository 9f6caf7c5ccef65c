"""The fleet patrol's own report: ``fleet.json`` and ``fleet.png`` beside each robot's report.

spec/fleet.md "The fleet patrol": under ``DIR`` each robot's report is ``DIR/<robot>/report.json``
(spec/report.md, an ordinary patrol's); this module writes what only the fleet knows from them:

* ``fleet.json``: per robot the pots it was given (``assigned``, those handed to it included, and
  which of them it ``received`` from a robot that dropped out), the ones it inspected (``done``),
  those it handed over and why (``handed_over``, ``handover_reason``: ``liveliness``, ``estop``,
  ``battery_low``), its outcome and robot time; for the fleet ``makespan_s`` (the longest robot
  time: the robots start together, so that is when the last one is home) and whether every pot
  was inspected by some robot (``complete``, what ``lupin fleet patrol``'s exit code says) with
  the pots no robot inspected.
* ``fleet.png``: the map, each robot's driven path and its pots in its colour (a filled disc
  inspected, a ring not; a pot handed over drawn in the colour of the robot that took it).

Robot time is the runtime clock's (``sim_time_s`` of a report): in the sim the robots share
one clock stepped in lock-step, so their times compare.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import cv2
import numpy as np

from hw.atomic_file import write_atomic
from mission.patrol.run_picture import canvas
from nav.map_render import render_map, to_pixel
from nav.occupancy import OccupancyMap

COLOURS = [(200, 90, 20), (40, 140, 230), (60, 160, 60), (160, 40, 160), (30, 30, 200), (150, 150, 0),
           (0, 100, 160), (120, 60, 200), (90, 90, 90)]
"""BGR, one per robot in the fleet's order (up to the console's 9), far apart in hue."""
REASONS = ("liveliness", "estop", "battery_low")
"""Why a robot hands its pots over (spec/fleet.md): its liveliness gone, an e-stop held longer
than ``fleet.handover_after``, battery low."""
INK, PAPER, GAP = (30, 30, 30), (255, 255, 255), 12
FONT = cv2.FONT_HERSHEY_SIMPLEX


@dataclass
class RobotRun:
    """One robot's share of a fleet patrol, as the dispatcher followed it."""

    robot: str
    assigned: list[str]
    """Pot ids it was sent, in its order (those handed to it appended)."""
    report: Mapping
    """Its report.json (spec/report.md)."""
    received: list[str] = field(default_factory=list)
    """Of ``assigned``, the pots handed to it from a robot that dropped out."""
    handed_over: list[str] = field(default_factory=list)
    """Pots it was sent but did not inspect, passed to the others."""
    handover_reason: str | None = None
    path_xy: np.ndarray | None = None
    """Its driven path in the fleet's map frame (N, 2), for the picture."""
    reports: list[str] | None = None
    """Its reports' files under the fleet's directory, one per patrol (default: ``<robot>/report.json``)."""

    def files(self) -> list[str]:
        return list(self.reports) if self.reports is not None else [f"{self.robot}/report.json"]

    def done(self) -> list[str]:
        return [p["id"] for p in self.report.get("pots", []) if p.get("status") == "inspected"]


def fleet_summary(mission: str, pots: Sequence[str], runs: Sequence[RobotRun], handovers: Sequence[Mapping] = ()) -> dict:
    """``fleet.json``'s document for the mission's ``pots`` (ids) and each robot's run;
    ``handovers``: each hand-over's pots, ``from``, ``to``, ``why`` and when (``at_s``)."""
    for r in runs:
        if r.handover_reason is not None and r.handover_reason not in REASONS:
            raise ValueError(f"{r.robot}: handover reason {r.handover_reason!r} is none of {REASONS}")
    inspected = {p for r in runs for p in r.done()}
    missing = [p for p in pots if p not in inspected]
    robots = {r.robot: {"assigned": list(r.assigned), "received": list(r.received), "done": r.done(),
                        "handed_over": list(r.handed_over), "handover_reason": r.handover_reason,
                        "outcome": r.report.get("outcome"), "robot_time_s": float(r.report.get("sim_time_s", 0.0)),
                        "report": next(iter(r.files()), None), "reports": r.files()} for r in runs}
    return {"mission": mission, "makespan_s": max((v["robot_time_s"] for v in robots.values()), default=0.0),
            "complete": not missing, "pots": {"total": len(pots), "inspected": len(pots) - len(missing),
                                              "not_inspected": missing},
            "robots": robots, "handovers": [dict(h) for h in handovers]}


def draw_fleet(occupancy: OccupancyMap | None, where: Mapping[str, tuple[float, float]],
               runs: Sequence[RobotRun]) -> np.ndarray:
    """BGR picture: the map, each robot's path and its pots in its colour, a legend below."""
    paths = [np.asarray(r.path_xy, float).reshape(-1, 2) if r.path_xy is not None else np.zeros((0, 2)) for r in runs]
    spots = np.array(list(where.values()), float).reshape(-1, 2)
    m, scale = canvas(occupancy, np.vstack([*paths, spots]), [], None)  # the pots are places here, not marks
    img = render_map(m, scale)
    h, w = img.shape[:2]

    def px(x: float, y: float) -> tuple[int, int]:
        c, r = to_pixel(m, scale, x, y)
        return min(max(c, 0), w - 1), min(max(r, 0), h - 1)

    radius = int(min(max(round(0.15 * scale / m.resolution), 5), 12))
    owner = {p: k for k, r in enumerate(runs) for p in r.done()}
    for k, (r, path) in enumerate(zip(runs, paths)):
        colour = COLOURS[k % len(COLOURS)]
        if len(path):
            cv2.polylines(img, [np.array([px(x, y) for x, y in path], np.int32)], False, colour, 2, cv2.LINE_AA)
            cv2.circle(img, px(*path[0]), 5, colour, -1, cv2.LINE_AA)
        for p in r.assigned:
            if p not in where or owner.get(p, k) != k:
                continue  # drawn by the robot that inspected it
            filled = p in owner
            cv2.circle(img, px(*where[p]), radius, colour, -1 if filled else 2, cv2.LINE_AA)
            if filled:
                cv2.circle(img, px(*where[p]), radius, INK, 1, cv2.LINE_AA)
    return np.vstack([img, _legend(runs, w)])


def _legend(runs: Sequence[RobotRun], width: int) -> np.ndarray:
    img = np.full((8 + 24 * max(1, len(runs)), width, 3), PAPER, np.uint8)
    img[0] = (200, 200, 200)
    for k, r in enumerate(runs):
        y = 8 + 24 * k + 12
        cv2.circle(img, (GAP + 8, y), 7, COLOURS[k % len(COLOURS)], -1, cv2.LINE_AA)
        text = f"{r.robot}: {len(r.done())}/{len(r.assigned)} pots"
        if r.handed_over:
            text += f", {len(r.handed_over)} handed over ({r.handover_reason})"
        cv2.putText(img, text, (GAP + 22, y + 5), FONT, 0.5, INK, 1, cv2.LINE_AA)
    return img


def write_fleet_report(out: Path, mission: str, pots: Mapping[str, tuple[float, float]], runs: Sequence[RobotRun],
                       occupancy: OccupancyMap | None = None, handovers: Sequence[Mapping] = ()) -> dict:
    """Write ``out/fleet.json`` and ``out/fleet.png`` (atomically); returns the summary.
    ``pots``: the mission's pots, id -> (x, y) in the fleet's map frame, in the mission's order."""
    summary = fleet_summary(mission, list(pots), runs, handovers)
    out.mkdir(parents=True, exist_ok=True)
    write_atomic(out / "fleet.json", (json.dumps(summary, indent=2) + "\n").encode())
    ok, png = cv2.imencode(".png", draw_fleet(occupancy, pots, runs))
    if not ok:
        raise RuntimeError("fleet.png: the picture did not encode")
    write_atomic(out / "fleet.png", png.tobytes())
    return summary
