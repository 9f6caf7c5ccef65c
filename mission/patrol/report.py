"""The patrol report (spec/report.md): one JSON document, rewritten atomically after every pot.

What the leaves found (``behaviours.visit.PotVisit``) becomes a pot entry here, and this is the
one place that decides what is an anomaly (the original's KIND_ANOMALY contract, left dead
there, reference/upstream.md):

==================  ==========================================================================
kind                when
==================  ==========================================================================
unreachable         every navigation attempt failed, after the others too; the pot is ``failed``
retried_later       the first go could not get there (why), the go after the other pots did
approach_blocked    something stood on the approach pose: inspected from a look beside it (why,
                    and how far off; ``mission.patrol.aside``)
arm_unavailable     the arm could not take the pot's inspection pose (latched servo, inactive
                    controller): the flower is unknown, the tag is still read
no_image            a camera gave no fresh frame in time (the step is recorded without it)
no_bloom            the wrist frame shows no bloom
bug                 a pest spot on a bloom or on a leaf (the detail says which, and how sure)
no_tag              no tag within ``patrol.tag_max_distance`` of the front camera
tag_mismatch        the pot's tag is not the one the mission expects
==================  ==========================================================================

Tags the front camera reads that the mission does not list are kept as ``discovered_tags`` with
their map position (the original's DiscoveredTag, also dead there), merged per id.

Every write goes to a temporary file in the same directory, then ``os.replace``: a reader (or a
crash) sees the previous complete report or the new one, never half of one. Images are written
the same way, before the report that names them.
"""
from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path
from typing import Callable, Protocol

from behaviours.visit import PotVisit
from hw.atomic_file import write_atomic
from hw.odometry import Pose2D
from mission.patrol.climate import ClimateSource
from mission.patrol.config import PatrolConfig
from mission.patrol.map_drift import in_mission_frame
from mission.patrol.run_picture import fit_thumbnail
from mission.patrol.mission_file import Mission, MissionPot
from mission.patrol.tag_sightings import PotEstimate, TagSightings
from nav.frames import compose, yaw_error
from perception.camera_pipeline import Frame
from perception.detections import TagRead

class ReportObserver(Protocol):
    """What follows a report as it is written (``mission.history.recorder.PatrolRecorder``)."""

    def recorded(self, pot: MissionPot, entry: dict, kinds: list[str]) -> None:
        """A pot's entry, just recorded, and its anomaly kinds."""

    def sections(self) -> dict:
        """More top-level keys for the report."""

    def finished(self, doc: dict) -> None:
        """The final report, just written."""


def pose_error(reached: Pose2D, goal: Pose2D) -> dict[str, float]:
    return {"xy": round(math.hypot(reached.x - goal.x, reached.y - goal.y), 4),
            "yaw": round(abs(yaw_error(reached, goal)), 4)}


class PatrolReport:
    """The report being written: ``record`` a finished pot, ``finish`` with the outcome."""

    def __init__(self, path: Path, mission: Mission, config: PatrolConfig, climate: ClimateSource,
                 runtime_now: Callable[[], float], wall_now: Callable[[], float], distance: Callable[[], float],
                 truth_error: Callable[[Pose2D], dict[str, float]] | None = None):
        self.path = Path(path)
        self.directory = self.path.parent
        self.directory.mkdir(parents=True, exist_ok=True)
        self.mission, self.config, self.climate = mission, config, climate
        self.runtime_now, self.wall_now, self.distance = runtime_now, wall_now, distance
        self.truth_error = truth_error
        self.t0, self.wall0 = runtime_now(), wall_now()
        self.pots: dict[str, dict] = {}
        self.anomalies: list[dict] = []
        self.discovered = TagSightings(config.front_camera_mount, config.plate_offset,
                                       max_distance=config.discovered_max_distance)
        self.estop_events: list[dict] = []
        self.outcome: str | None = None
        self.observers: list[ReportObserver] = []
        """Told of each pot as it is recorded and of the end (the patrol history); their
        ``sections`` are more top-level keys of the report (``changes``)."""
        self._listed_tags = {p.tag for p in mission.pots if p.tag is not None}

    # --- pots ----------------------------------------------------------------------------
    def pots_tag(self, visit: PotVisit) -> TagRead | None:
        """The pot's own tag: the nearest read close enough to be on this pot's plate, or the
        read that placed the pot (a moved pot's plate may leave the last frame)."""
        near = next((t for t in visit.tags if t.distance <= self.config.tag_max_distance), None)
        return near or visit.own_tag

    def record(self, pot: MissionPot, visit: PotVisit, goal: Pose2D) -> None:
        """A pot's branch has ended: its entry, its anomalies and images, then the report."""
        inspected = visit.arrived is not None and "search" not in visit.failures
        anomalies: list[tuple[str, str]] = []
        extra: dict[str, dict] = {}
        if "search" in visit.failures:
            anomalies.append(("not_found", visit.failures["search"]))
        elif not inspected:
            anomalies.append(("unreachable", f"{visit.attempts} attempt(s): {visit.failures.get('approach', '')}"))
        elif visit.deferred:
            anomalies.append(("retried_later", f"inspected after the other pots; the first go: {visit.deferred}"))
        if inspected and visit.aside:
            anomalies.append(("approach_blocked", visit.aside))
        moved = _moved(pot, visit)
        if moved is not None:
            anomalies.append(("moved", moved.pop("detail")))
            extra["moved"] = moved
        if "arm" in visit.failures:
            anomalies.append(("arm_unavailable", visit.failures["arm"]))
        for step in ("wrist", "front"):
            if step in visit.failures:
                anomalies.append(("no_image", f"{step} camera: {visit.failures[step]}"))
        entry = _entry(pot, "inspected" if inspected else "failed", visit.attempts)
        if visit.located is not None:
            entry["located"] = {k: round(v, 3) for k, v in zip(("x", "y", "facing"), visit.located)}
        if visit.failures:
            entry["failures"] = dict(visit.failures)
        if inspected:
            entry["approach_error"] = pose_error(visit.arrived, goal)
            if self.truth_error is not None:
                entry["truth_error"] = self.truth_error(goal)
        if visit.flower is not None:
            f = visit.flower
            entry["flower"] = {"color": f.flower, "blooms": f.count, "bug": f.bug, "confidence": round(f.confidence, 3)}
            entry["wrist_view"] = visit.view
            if f.flower == "none":
                anomalies.append(("no_bloom", "no bloom in the wrist frame"))
            if f.bug:
                pest = f.pest
                where = "a leaf" if pest is not None and pest.on == "leaf" else f"a {f.flower} bloom"
                sure = f" (confidence {pest.confidence:.2f})" if pest is not None else ""
                anomalies.append(("bug", f"dark spot on {where}{sure}"))
        if visit.front is not None and "search" not in visit.failures:  # not found: no plate to judge
            tag = self.pots_tag(visit)
            entry["tag_read"] = tag.id if tag is not None else None
            if tag is None:
                anomalies.append(("no_tag", f"no tag within {self.config.tag_max_distance:g} m of the front camera"))
            elif pot.tag is not None and tag.id != pot.tag:
                anomalies.append(("tag_mismatch", f"expected tag {pot.tag}, read {tag.id}"))
        # keyed by the tag read, never the tag the mission expects: a pot whose tag was not read
        # (or a pot swapped for another) must not be given another plant's climate
        climate = self.climate.reading(entry["tag_read"]) if entry["tag_read"] is not None else None
        if climate:
            entry["climate"] = climate
        for name, frame in (("front", visit.front), ("wrist", visit.wrist)):
            if frame is not None:
                entry["images"].append(self._save_image(f"{pot.id}_{name}.jpg", frame))
        # on disk now: keep only the run picture's thumbnail, or a day's patrol holds ~2 MB a pot
        visit.front = None
        if visit.wrist is not None:
            visit.wrist = replace(visit.wrist, image=fit_thumbnail(visit.wrist.image))
        self.pots[pot.id] = entry
        self.anomalies.extend({"kind": k, "pot": pot.id, "detail": d, **extra.get(k, {})} for k, d in anomalies)
        visit.done = True
        for observer in self.observers:
            observer.recorded(pot, entry, [k for k, _ in anomalies])
        self.write()

    def revise_moved(self, pot: MissionPot, visit: PotVisit) -> None:
        """The pot's ``moved`` anomaly as its verdict stands now (judged again at the patrol's
        end, ``PotFinder.rejudge``); the history keeps what was recorded at the pot."""
        self.anomalies = [a for a in self.anomalies if not (a["pot"] == pot.id and a["kind"] == "moved")]
        moved = _moved(pot, visit)
        if moved is not None:
            self.anomalies.append({"kind": "moved", "pot": pot.id, **moved})

    def _save_image(self, name: str, frame: Frame) -> str:
        write_atomic(self.directory / name, frame.jpeg)
        return name

    # --- tags seen en route ------------------------------------------------------------------
    def saw(self, reads: tuple[TagRead, ...], robot: Pose2D) -> None:
        """Tags read from the robot's map pose ``robot``: the unlisted ones near enough to place
        become discovered tags, every read of one id fused (``mission.patrol.tag_sightings``)."""
        self.discovered.add(tuple(r for r in reads if r.id not in self._listed_tags), robot)

    # --- the document --------------------------------------------------------------------
    def document(self) -> dict:
        """The report as it stands: pots in the order they were finished; once the outcome is
        known, the pots never reached follow as ``skipped``."""
        pots = list(self.pots.values())
        if self.outcome is not None:
            pots += [_entry(p, "skipped") for p in self.mission.pots if p.id not in self.pots]
        return {
            "mission": self.mission.name,
            "outcome": self.outcome,
            "sim_time_s": round(self.runtime_now() - self.t0, 3),
            "wall_time_s": round(self.wall_now() - self.wall0, 3),
            "distance_m": round(self.distance(), 3),
            "pots": pots,
            "anomalies": self.anomalies,
            "discovered_tags": [_discovered(e, self.config.plate_offset) for e in self.discovered.estimates()],
            "estop_events": self.estop_events,
        }

    def write(self, **extra) -> dict:
        """Write the report as it stands (plus ``extra`` top-level keys); returns it."""
        doc = self.document()
        for observer in self.observers:
            doc.update(observer.sections())
        doc.update(extra)
        write_atomic(self.path, json.dumps(doc, indent=2).encode())
        return doc

    def finish(self, outcome: str, **extra) -> dict:
        """The final write: the outcome, and pots never reached marked ``skipped`` with an
        anomaly saying why (the patrol ended first), so every pot not inspected has one."""
        self.outcome = outcome
        self.anomalies.extend({"kind": "skipped", "pot": p.id, "detail": f"not visited: the patrol ended {outcome}"}
                              for p in self.mission.pots if p.id not in self.pots)
        doc = self.write(**extra)
        for observer in self.observers:
            observer.finished(doc)
        return doc


def _moved(pot: MissionPot, visit: PotVisit) -> dict | None:
    """A moved pot's anomaly fields (``detail``, and where it stands in the mission's frame), or
    None when it has not moved."""
    if not visit.moved:
        return None
    x, y, facing = in_mission_frame(visit)
    off = math.hypot(x - pot.x, y - pot.y)
    turn = math.remainder(facing - pot.facing, 2 * math.pi)
    drift = f" (the map's drift there, {math.hypot(*visit.drift):.2f} m, taken out)" if any(visit.drift) else ""
    return {"detail": f"{off:.2f} m from the mission's position, turned {turn:+.2f} rad{drift}",
            "x": round(x, 3), "y": round(y, 3), "facing": round(facing, 3)}


def _discovered(e: PotEstimate, plate_offset: float) -> dict:
    """A discovered tag: where the tag is (spec/report.md), and the pot it puts there."""
    x, y = e.x + plate_offset * math.cos(e.facing), e.y + plate_offset * math.sin(e.facing)
    return {"id": e.tag, "x": round(x, 3), "y": round(y, 3), "sightings": e.sightings,
            "pot": {"x": round(e.x, 3), "y": round(e.y, 3), "facing": round(e.facing, 3)}}


def not_inspected(doc: dict) -> dict[str, int]:
    """Pots not inspected, counted by why (their first anomaly: ``unreachable``, ``skipped``, ...)."""
    why = {}
    for a in doc["anomalies"]:
        why.setdefault(a["pot"], a["kind"])
    counts: dict[str, int] = {}
    for p in doc["pots"]:
        if p["status"] != "inspected":
            kind = why.get(p["id"], p["status"])
            counts[kind] = counts.get(kind, 0) + 1
    return counts


def _entry(pot: MissionPot, status: str, attempts: int = 0) -> dict:
    """A pot's entry before anything was found (spec/report.md's required keys, plus where)."""
    return {"id": pot.id, "status": status, "attempts": attempts, "tag_expected": pot.tag, "tag_read": None,
            "flower": None, "x": pot.x, "y": pot.y, "images": []}
