"""The `lupin patrol` job: the mission tree over the whole stack, and its report directory.

A robot with navigation (sim or hardware), its two camera pipelines, the patrol tree ticking on
the scheduler at ``patrol.tick_rate``, and the report directory: ``config.yaml`` first (so even
a run killed at once says how it was configured), ``report.json`` rewritten after every pot with
the pot's images, and at the end ``map.yaml``/``map.pgm`` (SLAM's map) and ``run.png``.

On the sim, ground truth is used for judging only: each pot's ``truth_error``
(:mod:`mission.jobs.sim_patrol`; this module never imports the simulator).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np
from py_trees.common import Status

from hw.atomic_file import write_atomic, write_png
from hw.collision_monitor import LIDAR_BLIND
from hw.odometry import Pose2D
from hw.people import nobody
from hw.power_policy import RATE as POWER_RATE
from mission.history.recorder import PatrolRecorder, start_recording
from mission.history.store import History
from mission.patrol.aisle_gate import AisleGate
from mission.patrol.climate import ClimateSource, NoClimate
from mission.patrol.faults import RATE as FAULT_RATE, Faults
from mission.patrol.monitor_holds import RATE as HOLDS_RATE, MonitorHolds
from mission.patrol.mission_file import Mission, dump_mission
from mission.patrol.mission_resume import MISSION_FILE
from mission.patrol.person_encounters import PersonEncounters
from mission.patrol.report import PatrolReport
from mission.patrol.run_picture import PotMark, contact_sheet, draw_run
from mission.patrol.tree import PatrolTree
from mission.runtime.config import LupinConfig, save_config
from mission.runtime.navigation import final_map
from mission.runtime.hw_runtime import start_hw_runtime
from mission.runtime.robot import Robot
from nav.map_io import save_map
from nav.navigator import Navigator
from nav.occupancy import OccupancyMap
from perception.camera_pipeline import camera_pipelines
from perception.config import PerceptionConfig
from perception.tag_reader import TagReader

if TYPE_CHECKING:  # the sim path's parts, named only in annotations
    from mission.jobs.events import EventPlayer
    from mission.jobs.navigate import NavigateRun

RESTART_WATCH_S = 3.0
"""Seconds a sim run goes on after a ``runtime_crash`` with the restarted, idle runtime, so the
judge sees what it came back as (engaged or not, the base still)."""

TRACE_RATE = 10.0
"""The driven path (the robot's map pose) is sampled at the lidar's 10 Hz for the picture."""


def reading_mission_tags(perception: PerceptionConfig, mission: Mission) -> PerceptionConfig:
    """The tag reader's whitelist plus every tag the mission expects: the mission file says which
    plates exist, and a greenhouse may print more than the original's 0..21."""
    listed = {p.tag for p in mission.pots if p.tag is not None}
    whitelist = tuple(sorted(set(perception.tag.whitelist) | listed))
    return perception.model_copy(update={"tag": perception.tag.model_copy(update={"whitelist": whitelist})})


@dataclass
class PatrolRun:
    robot: Robot
    nav: Navigator
    tree: PatrolTree
    report: PatrolReport
    close: Callable[[], None]
    path: list[tuple[float, float]] = field(default_factory=list)
    """The robot's map pose as it believed it, at 10 Hz."""
    sim: "NavigateRun | None" = None
    """The sim under it, for judging only (truth); None on the robot."""
    events: "EventPlayer | None" = None
    """The events file being played into the sim run, if any."""
    history: PatrolRecorder | None = None
    """The patrol being written into the history (``mission.history``); None when it is off."""
    crashed: str = ""
    """Why the run ended in a runtime crash ('' when it did not)."""
    _crash_at: float | None = None

    @property
    def done(self) -> bool:
        if self._crash_at is not None:
            return self.robot.scheduler.clock.now() >= self._crash_at + RESTART_WATCH_S
        return bool(self.tree.lidar.given_up) or self.tree.root.status in (Status.SUCCESS, Status.FAILURE)

    def crash(self, now: float) -> None:
        """The runtime dies mid-patrol and its service starts it again (sim, ``runtime_crash``):
        the patrol is gone with its memory (its goal cancelled, the tree never ticked again), the
        robot's services come back from their state directory, idle."""
        self.abort()
        self.robot.restart(now)
        e = self.robot.estop
        self.crashed = (f"the runtime crashed at t={now - self.report.t0:.1f} s and was restarted: soft e-stop "
                        + (f"ENGAGED ({e.held_since_start})" if e.soft else "released"))
        self._crash_at = now

    def led_state(self) -> str:
        """What the status strip shows of this patrol (``hw.leds.pick_state``'s mission)."""
        if self.done:
            return "done" if self.outcome() == "completed" else "failed"
        holds = self.tree.holds
        return "paused" if holds.paused or holds.latched else "running"

    def outcome(self) -> str:
        if self.crashed or self.tree.lidar.given_up:
            return "aborted"
        if self.tree.battery_low:
            return "battery_low"
        if self.tree.root.status is not Status.SUCCESS or "home" in self.tree.notes:
            return "failed"
        return "completed"

    def step(self) -> None:
        self.robot.scheduler.step()

    def abort(self) -> None:
        """Stop the tree where it is: its running leaves cancel what they started (the
        navigation goal; the arm holds), and it is not ticked again."""
        self.robot.scheduler.cancel("mission")
        self.tree.root.stop(Status.INVALID)

    @property
    def elapsed(self) -> float:
        """Runtime seconds since the mission started."""
        return self.robot.scheduler.clock.now() - self.report.t0

    def finish(self, outcome: str, reason: str = "") -> dict:
        """The end of a run: SLAM's map, the picture, and the report's final write."""
        self.robot.scheduler.cancel("patrol.trace")
        self.robot.scheduler.cancel("patrol.holds")
        self.robot.scheduler.cancel("patrol.people")
        self.robot.scheduler.cancel("patrol.faults")
        self.robot.scheduler.cancel("patrol.energy")
        self.nav.keep_out = None  # the fleet's aisles bound this patrol's drives, not the next command's
        occupancy = final_map(self.nav, self.robot.scheduler)
        directory = self.report.directory
        if occupancy is not None:
            save_map(occupancy.cropped(), directory / "map.yaml")
        write_png(directory / "run.png", self.picture(occupancy))
        sheet = contact_sheet(self._marks())
        if sheet is not None:
            write_png(directory / "contact.png", sheet)
        write_atomic(directory / "tree.txt", (self.tree.render() + "\n").encode())
        for pot in self.tree.finder.rejudge(self.tree.visits):  # moved verdicts made with no drift to go by
            self.report.revise_moved(pot, self.tree.visits[pot.id])
        extra = {"notes": self.tree.notes} if self.tree.notes else {}
        if self.events is not None and self.events.applied:
            extra["events"] = self.events.applied
        if reason or self.crashed or self.tree.root.status is Status.FAILURE:
            extra["reason"] = reason or self.crashed or self.tree.failure()
        elif self.tree.lidar.given_up:
            extra["reason"] = self.tree.lidar.given_up
        return self.report.finish(outcome, **extra)

    def picture(self, occupancy: OccupancyMap | None) -> np.ndarray:
        """The map, the path the robot believed it drove, every pot by its result, thumbnails."""
        home = self.tree.mission.home
        return draw_run(occupancy, np.array(self.path, dtype=float).reshape(-1, 2), self._marks(), (home.x, home.y))

    def _marks(self) -> list[PotMark]:
        marks = []
        for pot in self.tree.mission.pots:
            entry = self.report.pots.get(pot.id, {"status": "skipped"})
            kinds = [a["kind"] for a in self.report.anomalies if a["pot"] == pot.id]
            color = (entry.get("flower") or {}).get("color", "")
            wrist = self.tree.visits[pot.id].wrist
            marks.append(PotMark(pot.id, pot.x, pot.y, entry["status"], bool(kinds),
                                 " ".join([pot.id, color, *kinds]).strip(), wrist.image if wrist is not None else None))
        return marks


def start_patrol(robot: Robot, nav: Navigator, mission: Mission, config: LupinConfig, perception: PerceptionConfig,
                 report_path: Path, wall_now: Callable[[], float], close: Callable[[], None],
                 climate: ClimateSource | None = None,
                 truth_error: Callable[[Pose2D], dict[str, float]] | None = None,
                 before_mission: Callable[[PatrolRun], None] = lambda run: None,
                 history: History | None = None, world: str | None = None, gate: AisleGate | None = None,
                 others: Sequence[tuple[float, float]] = ()) -> PatrolRun:
    """Schedule the tree (and the path trace) on a running robot with navigation;
    ``before_mission(run)`` schedules what must run before the tree at a shared instant.
    With ``history`` the patrol is recorded there as it goes (``world``: the sim world's name)
    and the report gains ``changes`` against the previous patrol of the same mission. ``gate``:
    a fleet's aisle locks (``mission.patrol.aisle_gate``; None: a robot alone). ``others``: the
    greenhouse's pots outside this mission (map frame), which the person tracker knows as pots
    too: measured on ``fleet.patrol_small``, a robot given a fleet's share took the other robots'
    pots for people standing still and waited 60 s for "a person in the only way"."""
    save_config(config, Path(report_path).parent)
    write_atomic(Path(report_path).parent / MISSION_FILE, dump_mission(mission).encode())  # what --resume reads
    perception = reading_mission_tags(perception, mission)
    clock = robot.scheduler.clock
    cameras = camera_pipelines(robot.hal.cameras, clock, perception)
    report = PatrolReport(Path(report_path), mission, config.patrol, climate or NoClimate(), clock.now, wall_now,
                          lambda: robot.base.odometry.distance, truth_error)
    tree = PatrolTree(mission, robot, nav, cameras, report, TagReader(perception.tag), config.patrol, gate=gate)
    report.estop_events = tree.holds.estop_events
    recorder = start_recording(history, mission, config.link.robot, world, Path(report_path))
    if recorder is not None:
        report.observers.append(recorder)
    holds = MonitorHolds(lambda: robot.monitor.verdict, nav.map_pose, report.t0)
    report.observers.append(holds)
    robot.scheduler.every("patrol.holds", HOLDS_RATE, holds.tick)
    pots = [(p.x, p.y) for p in mission.pots] + list(others)
    tracked = robot.people.watch(pots, config.patrol.pot_radius) if robot.people else nobody
    people = PersonEncounters(tracked, lambda: robot.base.odometry.pose, lambda: robot.monitor.verdict, report.t0,
                              config.nav.costmap.robot_radius)
    report.observers.append(people)
    robot.scheduler.every("patrol.people", HOLDS_RATE, people.tick)
    faults = Faults({"lidar_blind": lambda: robot.monitor.fault == LIDAR_BLIND,
                     "lidar_lost": lambda: tree.lidar.lost_for() is not None}, report.t0)
    report.observers.append(faults)
    robot.scheduler.every("patrol.faults", FAULT_RATE, faults.tick)
    robot.scheduler.every("patrol.energy", POWER_RATE,
                          lambda now: tree.energy.sample(robot.power.reading, robot.base.odometry.pose))
    run = PatrolRun(robot, nav, tree, report, close, history=recorder)
    robot.mission_state = run.led_state

    def trace(now: float) -> None:
        pose = nav.map_pose()
        run.path.append((pose.x, pose.y))

    robot.scheduler.every("patrol.trace", TRACE_RATE, trace)
    before_mission(run)

    def tick(now: float) -> None:
        tree.root.tick_once()
        if run.done:  # ticking an ended tree would start the patrol over
            robot.scheduler.cancel("mission")

    robot.scheduler.every("mission", config.patrol.tick_rate, tick)
    return run


def start_hw_patrol(mission: Mission, config: LupinConfig, report_path: Path,
                    wall_now: Callable[[], float], history: History | None = None) -> PatrolRun:
    """The patrol on the robot: its devices (a missing one is a clear error before anything
    moves), the wall clock, no climate source, nothing to judge against."""
    rt = start_hw_runtime(config)
    return start_patrol(rt.robot, rt.nav, mission, config, config.perception, report_path, wall_now, rt.close,
                        history=history)


def run_to_end(run: PatrolRun, on_step: Callable[[PatrolRun], None] = lambda r: None,
               limit: float | None = None) -> dict:
    """Tick until the tree ends, then finish; Ctrl-C, or ``limit`` seconds of runtime clock,
    aborts (the goal cancelled, the report finished ``aborted`` with what was done). The run is
    closed whatever happens, and what the history has still to write is written."""
    try:
        try:
            while not run.done:
                if limit is not None and run.elapsed >= limit:
                    run.abort()
                    return run.finish("aborted", f"time limit: still running after {limit:g} s")
                run.step()
                on_step(run)
        except KeyboardInterrupt:
            run.abort()
            return run.finish("aborted")
        return run.finish(run.outcome())
    finally:
        run.close()
        if run.history is not None:
            run.history.wait()
